// The defaults of Accel's recording entry points, for structures that record no steps.
#include "thicket/accel/accel.h"

namespace thicket {

Hit Accel::intersect(const Ray& ray, TraversalRecorder& recorder) const {
    RayCounters counters;
    const Hit hit = intersect(ray, counters);
    recorder.nodes += counters.nodes;
    recorder.prims += counters.prims;
    recorder.detailed = false;
    return hit;
}

bool Accel::for_each_node(const std::function<void(const NodeBox&)>&) const { return false; }

}  // namespace thicket
