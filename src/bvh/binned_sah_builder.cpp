// Binned SAH builder (Wald 2007): per axis, centroids fall into `bins` equal bins; the SAH is
// evaluated at the bins-1 planes between them from prefix sums, and the best plane is the pivot
// of the partition. A top node is binned chunk by chunk on several threads; bins merge exactly
// (min/max and integer counts), so the split never depends on the number of threads.
#include <array>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "splitter.h"

namespace thicket::bvh_build {
namespace {

constexpr uint32_t kMaxBins = 256;  // the option's upper bound (register_bvh.cpp)

/// Bins of all three axes for one range: what a chunk produces and what chunks merge into.
struct Bins {
    std::array<std::array<Aabb, kMaxBins>, 3> bounds;
    std::array<std::array<uint32_t, kMaxBins>, 3> counts;

    void clear(uint32_t bins) {
        for (int a = 0; a < 3; ++a) {
            std::fill_n(bounds[a].begin(), bins, Aabb{});
            std::fill_n(counts[a].begin(), bins, 0u);
        }
    }
    void merge(const Bins& o, uint32_t bins) {
        for (int a = 0; a < 3; ++a)
            for (uint32_t b = 0; b < bins; ++b) {
                bounds[a][b].grow(o.bounds[a][b]);
                counts[a][b] += o.counts[a][b];
            }
    }
};

class BinnedSahSplitter final : public Splitter {
public:
    explicit BinnedSahSplitter(BuildContext& ctx) : Splitter(ctx), bins_(uint32_t(ctx.options.bins)) {}

    Split split(const NodeRange& node, unsigned threads) override {
        const bool top = node.count >= kParallelNodeSize;
        const Aabb cb = centroid_bounds(ctx_, node, top ? threads : 1);
        Vec3 scale;
        for (int a = 0; a < 3; ++a) {
            const float extent = cb.max[a] - cb.min[a];
            scale[a] = extent > 0.0f ? float(bins_) / extent : 0.0f;
        }

        // Small nodes bin into a thread's own buffer; top nodes into one buffer per chunk,
        // merged in chunk order.
        thread_local Bins bins;
        if (!top) {
            bins.clear(bins_);
            bin_range(node.first, node.first + node.count, cb, scale, bins);
        } else {
            // Top nodes are split by the build's calling thread alone, one at a time, so one
            // set of chunk buffers serves them all.
            partial_.resize(std::max(partial_.size(), chunk_count(node.count)));
            for_each_chunk(node.first, node.count, threads, [&](size_t c, uint32_t lo, uint32_t hi) {
                partial_[c].clear(bins_);
                bin_range(lo, hi, cb, scale, partial_[c]);
            });
            bins.clear(bins_);
            for (size_t c = 0; c < chunk_count(node.count); ++c) bins.merge(partial_[c], bins_);
        }

        float best_cost = kInfinity;
        int best_axis = -1;
        uint32_t best_plane = 0;
        std::array<float, kMaxBins> right_area;
        std::array<uint32_t, kMaxBins> right_count;
        for (int axis = 0; axis < 3; ++axis) {
            if (!(scale[axis] > 0.0f)) continue;
            const auto& counts = bins.counts[axis];
            sah_sweep(
                bins_, [&](uint32_t b) -> const Aabb& { return bins.bounds[axis][b]; },
                [&](uint32_t b) { return counts[b]; }, [&](uint32_t b) { return counts[b]; }, node.bounds.half_area(),
                ctx_.options.sah_block, right_area.data(), right_count.data(),
                [&](uint32_t p, float cost, uint32_t, uint32_t) {
                    if (cost < best_cost) {
                        best_cost = cost;
                        best_axis = axis;
                        best_plane = p;
                    }
                });
        }
        if (best_axis < 0) return {};
        const bool may_stop = node.count <= uint32_t(ctx_.options.max_leaf);
        if (may_stop && best_cost >= sah_leaf_cost(node.count, ctx_.options.sah_block)) return {};

        // Partition with the same bin function, so the sides match the counts evaluated above.
        const auto& c = ctx_.prims.centroids;
        const float lo = cb.min[best_axis], s = scale[best_axis];
        const Partition part = partition_node(ctx_, node, threads, [&](uint32_t prim) {
            return bin_of(c[prim][best_axis], lo, s) <= best_plane;
        });
        Split split;
        split.left_count = part.left;
        split.axis = best_axis;
        split.bounded = true;
        split.centroids_known = true;
        split.left_centroids = part.left_centroids;
        split.right_centroids = part.right_centroids;
        for (uint32_t b = 0; b < bins_; ++b)
            (b <= best_plane ? split.left_bounds : split.right_bounds).grow(bins.bounds[best_axis][b]);
        return split;
    }

private:
    /// Adds indices[begin, end) to the bins of every axis with a positive extent (the others'
    /// bins may be filled too: the sweep never reads them).
    void bin_range(uint32_t begin, uint32_t end, const Aabb& cb, Vec3 scale, Bins& out) const {
#if defined(__SSE2__)
        bin_range_sse(begin, end, cb, scale, out);
#else
        const auto& idx = ctx_.indices;
        const auto& c = ctx_.prims.centroids;
        const auto& b = ctx_.prims.bounds;
        for (uint32_t k = begin; k < end; ++k) {
            const uint32_t prim = idx[k];
            for (int a = 0; a < 3; ++a) {
                if (!(scale[a] > 0.0f)) continue;
                const uint32_t bin = bin_of(c[prim][a], cb.min[a], scale[a]);
                out.bounds[a][bin].grow(b[prim]);
                ++out.counts[a][bin];
            }
        }
#endif
    }

#if defined(__SSE2__)
    /// bin_range with the three axes in one pass of 4-lane arithmetic: each centroid's three bins
    /// from one subtraction, multiplication and clamp, each bin box grown by one min and one max.
    /// Bitwise what the scalar loop computes: the same (v - lo) * scale per axis; max(f, 0) then
    /// min(f, bins - 1) truncated is bin_of's clamp (a NaN f gives 0, as bin_of's !(f > 0));
    /// _mm_min_ps(p, acc) is std::min(acc, p) and _mm_max_ps(p, acc) std::max(acc, p), NaN and
    /// signed zeros included (both keep acc unless p compares beyond it).
    void bin_range_sse(uint32_t begin, uint32_t end, const Aabb& cb, Vec3 scale, Bins& out) const {
        struct alignas(16) Box4 {
            __m128 lo, hi;
        };
        std::array<std::array<Box4, kMaxBins>, 3> box;
        const __m128 inf = _mm_set1_ps(kInfinity), ninf = _mm_set1_ps(-kInfinity);
        for (auto& axis : box)
            for (uint32_t bin = 0; bin < bins_; ++bin) axis[bin] = {inf, ninf};
        const __m128 lo = _mm_setr_ps(cb.min.x, cb.min.y, cb.min.z, 0.0f);
        const __m128 sc = _mm_setr_ps(scale.x, scale.y, scale.z, 0.0f);
        const __m128 top = _mm_set1_ps(float(bins_ - 1)), zero = _mm_setzero_ps();
        const uint32_t* idx = ctx_.indices.data();
        const Vec3* c = ctx_.prims.centroids.data();
        const Aabb* b = ctx_.prims.bounds.data();
        alignas(16) int32_t bin[4];
        for (uint32_t k = begin; k < end; ++k) {
            const uint32_t prim = idx[k];
            // Loads within the 12-byte Vec3 and the 24-byte Aabb, never past them.
            const __m128 cxy = _mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(&c[prim].x)));
            const __m128 cen = _mm_movelh_ps(cxy, _mm_load_ss(&c[prim].z));
            const __m128 f = _mm_mul_ps(_mm_sub_ps(cen, lo), sc);
            _mm_store_si128(reinterpret_cast<__m128i*>(bin), _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(f, zero), top)));
            const __m128 pmin = _mm_loadu_ps(&b[prim].min.x);                           // min.xyz, max.x
            const __m128 zmax = _mm_loadu_ps(&b[prim].min.z);                           // min.z, max.xyz
            const __m128 pmax = _mm_shuffle_ps(zmax, zmax, _MM_SHUFFLE(3, 3, 2, 1));   // max.xyz
            for (int a = 0; a < 3; ++a) {
                Box4& dst = box[size_t(a)][uint32_t(bin[a])];
                dst.lo = _mm_min_ps(pmin, dst.lo);
                dst.hi = _mm_max_ps(pmax, dst.hi);
                ++out.counts[size_t(a)][uint32_t(bin[a])];
            }
        }
        alignas(16) float l[4], h[4];
        for (int a = 0; a < 3; ++a)
            for (uint32_t i = 0; i < bins_; ++i) {
                _mm_store_ps(l, box[size_t(a)][i].lo);
                _mm_store_ps(h, box[size_t(a)][i].hi);
                out.bounds[size_t(a)][i].grow(Aabb{{l[0], l[1], l[2]}, {h[0], h[1], h[2]}});
            }
    }
#endif

    /// Bin of a centroid coordinate; NaN and out-of-range values clamp, never an invalid cast.
    uint32_t bin_of(float v, float lo, float scale) const {
        const float f = (v - lo) * scale;
        if (!(f > 0.0f)) return 0;
        return f < float(bins_) ? std::min(uint32_t(f), bins_ - 1) : bins_ - 1;
    }

    uint32_t bins_;
    std::vector<Bins> partial_;  ///< per-chunk bins of the top node being split
};

}  // namespace

std::unique_ptr<Splitter> make_binned_sah_splitter(BuildContext& ctx) {
    return std::make_unique<BinnedSahSplitter>(ctx);
}

}  // namespace thicket::bvh_build
