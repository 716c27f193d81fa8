// Accel's batch queries: one parallel loop for every structure; what a thread does with its share
// is the structure's (intersect_chunk / occluded_chunk).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/accel/ray_order.h"
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

namespace {

/// A worker's scratch for reordered blocks.
template <class Answer>
struct ReorderScratch {
    RayOrder order;
    std::vector<Ray> rays;
    std::vector<Answer> answers;
};

/// out[i] is the answer to rays[i]: answer(rays, answers) answers a chunk of at most kBatchGrain
/// rays on the calling thread. Reordered (BatchOptions::reorder) unless the batch is coherent or
/// short: the rest of each block whose second chunk proves costly (accel/ray_order.h) is sorted,
/// traced in that order and its answers put back in place.
template <class Answer, class AnswerChunk>
void answer_batch(std::span<const Ray> rays, std::span<Answer> out, const BatchOptions& options, AnswerChunk&& answer) {
    const double from_ns = reorder_from(options);
    if (std::isinf(from_ns) || rays.size() < kReorderMin) {
        parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
            answer(rays.subspan(begin, end - begin), out.subspan(begin, end - begin));
            if (options.progress) options.progress(end - begin);
        });
        return;
    }
    const size_t block = reorder_block(rays.size(), resolve_threads(options.threads));
    auto chunks = [&](std::span<const Ray> in, std::span<Answer> answers) {
        for (size_t k = 0; k < in.size(); k += kBatchGrain) {
            const size_t m = std::min(kBatchGrain, in.size() - k);
            answer(in.subspan(k, m), answers.subspan(k, m));
            if (options.progress) options.progress(m);
        }
    };
    parallel_for_with<ReorderScratch<Answer>>(rays.size(), block, options.threads,
                                              [&](size_t begin, size_t end, ReorderScratch<Answer>& s) {
        // The first two chunks as given, the second timed (the first may find the structure, or
        // this block's rays, out of the cache): cheap rays trace the rest of the block as given too.
        const size_t probe = std::min(end, begin + kBatchGrain), from = std::min(end, probe + kBatchGrain);
        const size_t n = end - from;
        chunks(rays.subspan(begin, probe - begin), out.subspan(begin, probe - begin));
        if (!costly_rays(from - probe, from_ns, [&] { chunks(rays.subspan(probe, from - probe), out.subspan(probe, from - probe)); }))
            return chunks(rays.subspan(from, n), out.subspan(from, n));
        s.order.sort(n, [&](size_t i, Vec3& org, Vec3& dir) { org = rays[from + i].org, dir = rays[from + i].dir; });
        s.rays.resize(n);
        s.answers.resize(n);
        for (size_t k = 0; k < n; ++k) s.rays[k] = rays[from + s.order.order[k]];
        chunks(s.rays, s.answers);
        for (size_t k = 0; k < n; ++k) out[from + s.order.order[k]] = s.answers[k];
    });
}

}  // namespace

void Accel::intersect(std::span<const Ray> rays, std::span<Hit> hits, const BatchOptions& options) const {
    check_ray_answers("closest-hit", rays.size(), hits.size());
    answer_batch<Hit>(rays, hits, options, [&](std::span<const Ray> chunk, std::span<Hit> answers) {
        intersect_chunk(chunk, answers, options.coherent);
    });
}

void Accel::occluded(std::span<const Ray> rays, std::span<uint8_t> out, const BatchOptions& options) const {
    check_ray_answers("any-hit", rays.size(), out.size());
    refuse_coherent("any-hit", options);
    answer_batch<uint8_t>(rays, out, options, [&](std::span<const Ray> chunk, std::span<uint8_t> answers) {
        occluded_chunk(chunk, answers);
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
