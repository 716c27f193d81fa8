// Point queries: closest point (with the bvh8 fallback), distance, occupancy and signed distance.
#include "thicket/query/point_queries.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

/// Directions for the parity test: none along an axis or a diagonal.
constexpr Vec3 kParityDirections[] = {{0.5741f, 0.6327f, 0.5193f}, {-0.6811f, 0.2412f, 0.6913f},
                                      {0.3174f, -0.8479f, 0.4247f}, {-0.4431f, -0.5077f, -0.7389f},
                                      {0.7823f, -0.2291f, -0.5792f}};
static_assert(std::size(kParityDirections) == kMaxParitySamples);

void check_point_answers(const char* query, size_t points, size_t answers) {
    if (points != answers)
        throw Error(std::string(query) + ": " + std::to_string(points) + " points but room for " +
                    std::to_string(answers) + " answers");
}

}  // namespace

void check_parity_samples(int nsamples) {
    if (nsamples < 1 || nsamples > kMaxParitySamples || nsamples % 2 == 0)
        throw Error("nsamples must be odd, between 1 and " + std::to_string(kMaxParitySamples) + ", got " +
                    std::to_string(nsamples));
}

size_t first_non_finite(std::span<const Vec3> points) {
    for (size_t i = 0; i < points.size(); ++i)
        if (!std::isfinite(points[i].x) || !std::isfinite(points[i].y) || !std::isfinite(points[i].z)) return i;
    return points.size();
}

void inside_by_parity(const Accel& accel, std::span<const Vec3> points, int nsamples, std::span<uint8_t> inside) {
    check_parity_samples(nsamples);
    check_point_answers("occupancy", points.size(), inside.size());
    Ray rays[kBatchGrain];
    for (size_t begin = 0; begin < points.size(); begin += kBatchGrain) {
        const size_t n = std::min(kBatchGrain, points.size() - begin);
        uint8_t votes[kBatchGrain] = {};
        for (int s = 0; s < nsamples; ++s) {
            for (size_t k = 0; k < n; ++k) rays[k] = {points[begin + k], 0.0f, kParityDirections[s], kInfinity};
            for (size_t k = 0; k < n; ++k) votes[k] += accel.count_hits(rays[k]) & 1;
        }
        for (size_t k = 0; k < n; ++k) inside[begin + k] = 2 * votes[k] > nsamples ? 1 : 0;
    }
}

const Accel& PointQueries::closest_accel() const {
    if (accel_.has_closest_point()) return accel_;
    std::call_once(fallback_once_, [&] {
        std::unique_ptr<Accel> helper = build_accel(kClosestPointSpec, scene_);
        if (!helper->has_closest_point()) helper->closest_point({0, 0, 0});  // throws the reason (shapes)
        fallback_ = std::move(helper);
    });
    return *fallback_;
}

void PointQueries::closest_points(std::span<const Vec3> points, std::span<NearestPoint> out,
                                  const BatchOptions& options) const {
    check_point_answers("closest points", points.size(), out.size());
    refuse_coherent("closest points", options);
    for_each_closest_chunk(points, options.threads, [&](size_t begin, size_t end, const NearestPoint* closest) {
        std::copy(closest, closest + (end - begin), out.begin() + std::ptrdiff_t(begin));
        if (options.progress) options.progress(end - begin);
    });
}

void PointQueries::distances(std::span<const Vec3> points, std::span<float> out, const BatchOptions& options) const {
    check_point_answers("distances", points.size(), out.size());
    refuse_coherent("distances", options);
    for_each_closest_chunk(points, options.threads, [&](size_t begin, size_t end, const NearestPoint* closest) {
        for (size_t i = begin; i < end; ++i) out[i] = closest[i - begin].distance;
        if (options.progress) options.progress(end - begin);
    });
}

void PointQueries::occupancy(std::span<const Vec3> points, std::span<uint8_t> out, int nsamples,
                             const BatchOptions& options) const {
    check_parity_samples(nsamples);
    check_point_answers("occupancy", points.size(), out.size());
    refuse_coherent("occupancy", options);
    parallel_for(points.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        inside_by_parity(accel_, points.subspan(begin, end - begin), nsamples, out.subspan(begin, end - begin));
        if (options.progress) options.progress(end - begin);
    });
}

void PointQueries::signed_distances(std::span<const Vec3> points, std::span<float> out, int nsamples,
                                    const BatchOptions& options) const {
    check_parity_samples(nsamples);
    check_point_answers("signed distances", points.size(), out.size());
    refuse_coherent("signed distances", options);
    for_each_closest_chunk(points, options.threads, [&](size_t begin, size_t end, const NearestPoint* closest) {
        uint8_t inside[kBatchGrain];
        inside_by_parity(accel_, points.subspan(begin, end - begin), nsamples, {inside, end - begin});
        for (size_t i = begin; i < end; ++i)
            out[i] = inside[i - begin] ? -closest[i - begin].distance : closest[i - begin].distance;
        if (options.progress) options.progress(end - begin);
    });
}

}  // namespace thicket
