// Binned SAH builder (Wald 2007): per axis, centroids fall into `bins` equal bins; the SAH is
// evaluated at the bins-1 planes between them from prefix sums, and the best plane is the pivot
// of an in-place partition.
#include <vector>

#include "splitter.h"

namespace thicket::bvh_build {
namespace {

class BinnedSahSplitter final : public Splitter {
public:
    explicit BinnedSahSplitter(BuildContext& ctx)
        : Splitter(ctx), bins_(uint32_t(ctx.options.bins)), bin_bounds_(bins_), bin_counts_(bins_), right_area_(bins_),
          right_count_(bins_) {}

    Split split(const NodeRange& node) override {
        const Aabb cb = centroid_bounds(ctx_, node);
        const auto& idx = ctx_.indices;
        const auto& c = ctx_.prims.centroids;
        float best_cost = kInfinity;
        int best_axis = -1;
        uint32_t best_plane = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = cb.max[axis] - cb.min[axis];
            if (!(extent > 0.0f)) continue;
            const float scale = float(bins_) / extent;
            std::fill(bin_bounds_.begin(), bin_bounds_.end(), Aabb{});
            std::fill(bin_counts_.begin(), bin_counts_.end(), 0u);
            for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                const uint32_t b = bin_of(c[idx[k]][axis], cb.min[axis], scale);
                bin_bounds_[b].grow(ctx_.prims.bounds[idx[k]]);
                ++bin_counts_[b];
            }
            // Right-to-left prefix: area and count of everything right of plane p (after bin p).
            Aabb acc;
            uint32_t count = 0;
            for (uint32_t p = bins_ - 1; p > 0; --p) {
                acc.grow(bin_bounds_[p]);
                count += bin_counts_[p];
                right_area_[p - 1] = acc.half_area();
                right_count_[p - 1] = count;
            }
            acc = Aabb{};
            count = 0;
            for (uint32_t p = 0; p + 1 < bins_; ++p) {
                acc.grow(bin_bounds_[p]);
                count += bin_counts_[p];
                if (count == 0 || right_count_[p] == 0) continue;
                const float cost = sah_split_cost(acc.half_area(), count, right_area_[p], right_count_[p],
                                                  node.bounds.half_area());
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = axis;
                    best_plane = p;
                }
            }
        }
        if (best_axis < 0) return {};
        if (best_cost >= sah_leaf_cost(node.count) && node.count <= uint32_t(ctx_.options.max_leaf)) return {};

        // Partition with the same bin function, so the sides match the counts evaluated above.
        const float scale = float(bins_) / (cb.max[best_axis] - cb.min[best_axis]);
        auto& indices = ctx_.indices;
        uint32_t i = node.first, j = node.first + node.count;
        while (i < j) {
            if (bin_of(c[indices[i]][best_axis], cb.min[best_axis], scale) <= best_plane)
                ++i;
            else
                std::swap(indices[i], indices[--j]);
        }
        return {i - node.first, best_axis};
    }

private:
    /// Bin of a centroid coordinate; NaN and out-of-range values clamp, never an invalid cast.
    uint32_t bin_of(float v, float lo, float scale) const {
        const float f = (v - lo) * scale;
        if (!(f > 0.0f)) return 0;
        return f < float(bins_) ? std::min(uint32_t(f), bins_ - 1) : bins_ - 1;
    }

    uint32_t bins_;
    std::vector<Aabb> bin_bounds_;
    std::vector<uint32_t> bin_counts_;
    std::vector<float> right_area_;
    std::vector<uint32_t> right_count_;
};

}  // namespace

std::unique_ptr<Splitter> make_binned_sah_splitter(BuildContext& ctx) {
    return std::make_unique<BinnedSahSplitter>(ctx);
}

}  // namespace thicket::bvh_build
