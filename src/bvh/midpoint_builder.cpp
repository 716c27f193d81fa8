// Midpoint builder: split the longest axis of the centroid bounds in the middle, partition in
// place (quicksort-style, the plane is the pivot). The SAH only decides whether to stop.
#include "splitter.h"

namespace thicket::bvh_build {
namespace {

class MidpointSplitter final : public Splitter {
public:
    using Splitter::Splitter;

    Split split(const NodeRange& node, unsigned threads) override {
        const Aabb cb = centroid_bounds(ctx_, node, node.count >= kParallelNodeSize ? threads : 1);
        const int axis = max_axis(cb.extent());
        const float pos = cb.center()[axis];
        if (!(cb.extent()[axis] > 0.0f)) return {};
        auto& idx = ctx_.indices;
        const auto& c = ctx_.prims.centroids;
        const Partition part = partition_node(ctx_, node, threads, [&](uint32_t prim) { return c[prim][axis] < pos; });
        const uint32_t left = part.left;
        const uint32_t i = node.first + left;
        if (left == 0 || left == node.count) return {};

        Aabb lb, rb;
        for (uint32_t k = node.first; k < i; ++k) lb.grow(ctx_.prims.bounds[idx[k]]);
        for (uint32_t k = i; k < node.first + node.count; ++k) rb.grow(ctx_.prims.bounds[idx[k]]);
        const uint32_t block = ctx_.options.sah_block;
        const float cost =
            sah_split_cost(lb.half_area(), left, rb.half_area(), node.count - left, node.bounds.half_area(), block);
        if (cost >= sah_leaf_cost(node.count, block) && node.count <= uint32_t(ctx_.options.max_leaf)) return {};
        Split split;
        split.left_count = left;
        split.axis = axis;
        split.bounded = true;
        split.left_bounds = lb;
        split.right_bounds = rb;
        split.centroids_known = true;
        split.left_centroids = part.left_centroids;
        split.right_centroids = part.right_centroids;
        return split;
    }
};

}  // namespace

std::unique_ptr<Splitter> make_midpoint_splitter(BuildContext& ctx) { return std::make_unique<MidpointSplitter>(ctx); }

}  // namespace thicket::bvh_build
