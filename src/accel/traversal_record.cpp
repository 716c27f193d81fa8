// The defaults of Accel's recording and drawing entry points, for structures that record no
// steps and draw nothing.
#include "thicket/accel/accel.h"

namespace thicket {

namespace {

/// query(counters) answered with plain counters; the recorder gets their totals, no steps.
template <class Query>
auto totals_only(TraversalRecorder& recorder, const Query& query) {
    RayCounters counters;
    const auto answer = query(counters);
    recorder.nodes += counters.nodes;
    recorder.prims += counters.prims;
    recorder.detailed = false;
    return answer;
}

}  // namespace

Hit Accel::intersect(const Ray& ray, TraversalRecorder& recorder) const {
    return totals_only(recorder, [&](RayCounters& c) { return intersect(ray, c); });
}

bool Accel::occluded(const Ray& ray, TraversalRecorder& recorder) const {
    return totals_only(recorder, [&](RayCounters& c) { return occluded(ray, c); });
}

bool Accel::for_each_node(const DrawnNodeVisitor&) const { return false; }

std::optional<DrawingLegend> Accel::drawing_legend() const { return std::nullopt; }

}  // namespace thicket
