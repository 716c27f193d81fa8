// Accel's batch queries: one parallel loop for every structure; what a thread does with its share
// is the structure's (intersect_chunk / occluded_chunk).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"
#include "thicket/util/prefetch.h"

namespace thicket {

void check_ray_answers(const char* query, size_t rays, size_t answers) {
    if (rays != answers)
        throw Error(std::string(query) + " batch: " + std::to_string(rays) + " rays but room for " +
                    std::to_string(answers) + " answers");
}

void refuse_coherent(const char* query, const BatchOptions& options) {
    if (options.coherent)
        throw Error(std::string(query) + " batch: coherent (the packet path) serves float closest-hit batches only; "
                    "no structure traces this query differently for coherent rays, so the hint is refused rather "
                    "than ignored");
}

void Accel::intersect(std::span<const Ray> rays, std::span<Hit> hits, const BatchOptions& options) const {
    check_ray_answers("closest-hit", rays.size(), hits.size());
    parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        intersect_chunk(rays.subspan(begin, end - begin), hits.subspan(begin, end - begin), options.coherent);
        if (options.progress) options.progress(end - begin);
    });
}

void Accel::occluded(std::span<const Ray> rays, std::span<uint8_t> out, const BatchOptions& options) const {
    check_ray_answers("any-hit", rays.size(), out.size());
    refuse_coherent("any-hit", options);
    parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        occluded_chunk(rays.subspan(begin, end - begin), out.subspan(begin, end - begin));
        if (options.progress) options.progress(end - begin);
    });
}

void Accel::all_hits(const Ray& ray, std::vector<Hit>& out) const {
    step_crossings(ray, [this](const Ray& rest) { return intersect(rest); }, out);
}

size_t merge_crossings(std::span<Hit> hits, std::vector<Hit>* out) {
    std::sort(hits.begin(), hits.end(),
              [](const Hit& a, const Hit& b) { return a.t < b.t || (a.t == b.t && a.prim < b.prim); });
    size_t count = 0;
    float last = 0.0f;
    for (const Hit& hit : hits)
        if (count == 0 || hit.t >= next_crossing_t(last)) {
            if (out) out->push_back(hit);
            last = hit.t;
            ++count;
        }
    return count;
}

uint32_t Accel::count_hits(const Ray& ray) const {
    std::vector<Hit> hits;
    all_hits(ray, hits);
    return uint32_t(hits.size());
}

NearestPoint Accel::closest_point(const Vec3&) const {
    throw Error(spec_ + ": closest-point queries are answered by brute, bvh and bvh8 over triangles only");
}

void Accel::count_hits(std::span<const Ray> rays, std::span<uint32_t> counts, const BatchOptions& options) const {
    check_ray_answers("count", rays.size(), counts.size());
    refuse_coherent("count", options);
    parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        // Cold rays, long per ray: the hardware prefetcher falls behind (BENCHMARKS.md, "The
        // module against the C++ batch API": counting from a Ray vector without this).
        prefetch_range(&rays[begin], (end - begin) * sizeof(Ray));
        for (size_t i = begin; i < end; ++i) counts[i] = count_hits(rays[i]);
        if (options.progress) options.progress(end - begin);
    });
}

HitLists Accel::all_hits(std::span<const Ray> rays, const BatchOptions& options) const {
    refuse_coherent("all-hits", options);
    // Each chunk collects its rays' hits apart; the chunks are then laid end to end in ray order.
    const size_t chunks = (rays.size() + kBatchGrain - 1) / kBatchGrain;
    std::vector<std::vector<Hit>> chunk_hits(chunks);
    HitLists lists;
    lists.splits.assign(rays.size() + 1, 0);
    parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        std::vector<Hit>& mine = chunk_hits[begin / kBatchGrain];
        prefetch_range(&rays[begin], (end - begin) * sizeof(Ray));
        for (size_t i = begin; i < end; ++i) {
            const size_t before = mine.size();
            all_hits(rays[i], mine);
            lists.splits[i + 1] = mine.size() - before;  // a count for now, a prefix sum below
        }
        if (options.progress) options.progress(end - begin);
    });
    for (size_t i = 0; i < rays.size(); ++i) lists.splits[i + 1] += lists.splits[i];
    lists.hits.reserve(lists.splits.back());
    for (const std::vector<Hit>& c : chunk_hits) lists.hits.insert(lists.hits.end(), c.begin(), c.end());
    return lists;
}

void Accel::closest_points(std::span<const Vec3> points, std::span<NearestPoint> out,
                           const BatchOptions& options) const {
    check_ray_answers("closest-point", points.size(), out.size());
    refuse_coherent("closest-point", options);
    parallel_for(points.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) out[i] = closest_point(points[i]);
        if (options.progress) options.progress(end - begin);
    });
}

void Accel::intersect_chunk(std::span<const Ray> rays, std::span<Hit> hits, bool) const {
    for (size_t i = 0; i < rays.size(); ++i) hits[i] = intersect(rays[i]);
}

void Accel::occluded_chunk(std::span<const Ray> rays, std::span<uint8_t> out) const {
    for (size_t i = 0; i < rays.size(); ++i) out[i] = occluded(rays[i]) ? 1 : 0;
}

}  // namespace thicket
