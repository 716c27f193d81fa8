// Full-sweep SAH builder: every position between consecutive centroids along each axis is a
// candidate. Centroids are sorted once per axis at the start; each split keeps all three orders
// by a stable partition, so the build is O(N log N) rather than a sort per node.
#include <algorithm>
#include <numeric>
#include <vector>

#include "splitter.h"

namespace thicket::bvh_build {
namespace {

class SweepSahSplitter final : public Splitter {
public:
    explicit SweepSahSplitter(BuildContext& ctx) : Splitter(ctx) {
        const size_t n = ctx.indices.size();
        const auto& c = ctx.prims.centroids;
        // The three sorts are independent: one per thread.
        parallel_for(3, 1, ctx.options.threads, [&](size_t begin, size_t end) {
            for (size_t a = begin; a < end; ++a) {
                const int axis = int(a);
                std::vector<uint32_t>& order = sorted_[a];
                order.resize(n);
                std::iota(order.begin(), order.end(), 0u);
                std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
                    return centroid_before(c[a][axis], a, c[b][axis], b);
                });
            }
        });
        goes_left_.resize(n);
        right_area_.resize(n);
        right_count_.resize(n);
        scratch_.resize(n);
    }

    Split split(const NodeRange& node, unsigned) override {
        float best_cost = kInfinity;
        int best_axis = -1;
        uint32_t best_left = 0;
        const auto& bounds = ctx_.prims.bounds;
        for (int axis = 0; axis < 3; ++axis) {
            const uint32_t* order = sorted_[axis].data() + node.first;
            // Plane p puts order[0..p] on the left; this range's own scratch slots (tasks run at once).
            sah_sweep(
                node.count, [&](uint32_t k) -> const Aabb& { return bounds[order[k]]; }, [](uint32_t) { return 1u; },
                [](uint32_t) { return 1u; }, node.bounds.half_area(), ctx_.options.sah_block,
                right_area_.data() + node.first, right_count_.data() + node.first,
                [&](uint32_t p, float cost, uint32_t, uint32_t) {
                    if (cost < best_cost) {
                        best_cost = cost;
                        best_axis = axis;
                        best_left = p + 1;
                    }
                });
        }
        if (best_axis < 0) return {};
        const bool may_stop = node.count <= uint32_t(ctx_.options.max_leaf);
        if (may_stop && best_cost >= sah_leaf_cost(node.count, ctx_.options.sah_block)) return {};
        apply(node, best_axis, best_left);
        return plain_split(best_left, best_axis);
    }

    Split median_split(const NodeRange& node) override {
        const auto& c = ctx_.prims.centroids;
        int axis = 0;
        float widest = -1.0f;
        for (int a = 0; a < 3; ++a) {
            const float extent = c[sorted_[a][node.first + node.count - 1]][a] - c[sorted_[a][node.first]][a];
            if (extent > widest) widest = extent, axis = a;
        }
        apply(node, axis, node.count / 2);
        return plain_split(node.count / 2, axis);
    }

private:
    /// Sends the first `left` primitives in `axis` order to the left child, keeping every axis
    /// order sorted (stable partition) and mirroring the result into the BVH's index array.
    void apply(const NodeRange& node, int axis, uint32_t left) {
        const uint32_t begin = node.first, end = node.first + node.count;
        for (uint32_t k = begin; k < end; ++k) goes_left_[sorted_[axis][k]] = (k - begin) < left;
        for (int a = 0; a < 3; ++a) {
            if (a == axis) continue;
            uint32_t* order = sorted_[a].data();
            uint32_t l = begin, r = begin;  // scratch_ slots of this range only: tasks run at once
            for (uint32_t k = begin; k < end; ++k) {
                if (goes_left_[order[k]])
                    order[l++] = order[k];
                else
                    scratch_[r++] = order[k];
            }
            std::copy(scratch_.begin() + begin, scratch_.begin() + r, order + l);
        }
        std::copy(sorted_[axis].begin() + begin, sorted_[axis].begin() + end, ctx_.indices.begin() + begin);
    }

    std::vector<uint32_t> sorted_[3];
    std::vector<uint8_t> goes_left_;
    std::vector<float> right_area_;
    std::vector<uint32_t> right_count_;
    std::vector<uint32_t> scratch_;
};

}  // namespace

std::unique_ptr<Splitter> make_sweep_sah_splitter(BuildContext& ctx) { return std::make_unique<SweepSahSplitter>(ctx); }

}  // namespace thicket::bvh_build
