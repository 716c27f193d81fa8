// Leaves made for blocks: below kBlockPackMax primitives, nodes are split where a whole number of
// blocks (BvhBuildOptions::sah_block) goes left. The right side then holds the node's count
// modulo the block size beyond whole blocks, and by induction a node of n primitives ends in
// leaves of ceil(n / block) blocks in all, the least possible: at most one partial block per
// such subtree. Binned splits could not promise that (the counts between bins are what they
// are), and bvh8's blocks were 75-82% full with them; Embree, weighing leaves in blocks, fills
// 87-93%.
#include <algorithm>
#include <array>

#include "splitter.h"

namespace thicket::bvh_build {

namespace {

/// Primitives the left side of a forced split takes: about half, rounded up to whole blocks
/// when the node holds more than one block.
uint32_t halving_count(uint32_t count, uint32_t block) {
    if (count <= block) return count / 2;
    const uint32_t half = (count / 2 + block - 1) / block * block;
    return half < count ? half : half - block;
}

}  // namespace

Split block_split(BuildContext& ctx, const NodeRange& node, uint32_t depth) {
    const uint32_t n = node.count, block = std::max(1u, ctx.options.sah_block);
    const bool aligned = n > block;
    const auto& centroids = ctx.prims.centroids;
    const auto& bounds = ctx.prims.bounds;
    uint32_t* idx = ctx.indices.data() + node.first;

    // Each axis's order of the node's primitives (kBlockPackMax of them at most: on the stack).
    std::array<std::array<uint32_t, kBlockPackMax>, 3> order;
    std::array<float, kBlockPackMax> right_area;
    std::array<uint32_t, kBlockPackMax> right_count;
    float best_cost = kInfinity;
    int best_axis = -1;
    uint32_t best_left = 0;
    const bool deep = depth >= kMaxSahDepth;  // past it only halving, which bounds the depth
    for (int axis = 0; axis < 3; ++axis) {
        uint32_t* o = order[size_t(axis)].data();
        std::copy(idx, idx + n, o);
        std::sort(o, o + n, [&](uint32_t a, uint32_t b) {
            return centroid_before(centroids[a][axis], a, centroids[b][axis], b);
        });
        if (deep) continue;
        sah_sweep(
            n, [&](uint32_t k) -> const Aabb& { return bounds[o[k]]; }, [](uint32_t) { return 1u; },
            [](uint32_t) { return 1u; }, node.bounds.half_area(), block, right_area.data(), right_count.data(),
            [&](uint32_t, float cost, uint32_t left, uint32_t) {
                if (aligned && left % block != 0) return;
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = axis;
                    best_left = left;
                }
            });
    }
    const bool may_stop = !deep && n <= uint32_t(ctx.options.max_leaf);
    if (may_stop && !(best_cost < sah_leaf_cost(n, block))) return {};  // NaN costs (NaN boxes) too
    if (best_axis < 0) {  // too deep, or no finite cost, and too big a leaf: halve on the widest axis
        Aabb cb;
        for (uint32_t k = 0; k < n; ++k) cb.grow(centroids[idx[k]]);
        best_axis = cb.empty() ? 0 : max_axis(cb.extent());
        best_left = halving_count(n, block);
    }

    // The chosen order becomes the range's; the children's boxes in that order, as a pass over
    // each child's range would grow them.
    const uint32_t* o = order[size_t(best_axis)].data();
    std::copy(o, o + n, idx);
    Split split;
    split.left_count = best_left;
    split.axis = best_axis;
    split.bounded = true;
    split.centroids_known = true;
    for (uint32_t k = 0; k < n; ++k) {
        const bool left = k < best_left;
        (left ? split.left_bounds : split.right_bounds).grow(bounds[o[k]]);
        (left ? split.left_centroids : split.right_centroids).grow(centroids[o[k]]);
    }
    return split;
}

}  // namespace thicket::bvh_build
