// Leaves made for blocks: below kBlockPackMax primitives, nodes are split where a whole number of
// blocks (BvhBuildOptions::sah_block) goes left. The right side then holds the node's count
// modulo the block size beyond whole blocks, and by induction a node of n primitives ends in
// leaves of ceil(n / block) blocks in all, the least possible: at most one partial block per
// such subtree. Binned splits could not promise that (the counts between bins are what they
// are), and bvh8's blocks were 75-82% full with them; Embree, weighing leaves in blocks, fills
// 87-93%.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <span>

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

/// A primitive's place in centroid_before's order along an axis as one integer: the coordinate's
/// bits made monotonic (-0 first made +0, which centroid_before holds equal; every NaN the
/// largest key) above the primitive id, so that integer order is centroid_before's exactly.
uint64_t centroid_key(float v, uint32_t prim) {
    uint32_t bits = 0xFFFFFFFFu;  // NaN: after every number
    if (v == v) {
        bits = std::bit_cast<uint32_t>(v + 0.0f);
        bits = (bits & 0x80000000u) ? ~bits : bits | 0x80000000u;
    }
    return uint64_t(bits) << 32 | prim;
}

/// Writes prims[0, n) to `out` in centroid_before's order along `axis`. Keys are gathered once
/// and insertion-sorted as integers: a node here holds at most kBlockPackMax primitives, where
/// std::sort's indirect comparisons (a centroid load and NaN tests per comparison) cost the
/// build a sixth of its time. The order is total, so the result is std::sort's exactly.
void sort_by_centroid(const uint32_t* prims, uint32_t n, std::span<const Vec3> centroids, int axis,
                      uint32_t* out) {
    std::array<uint64_t, kBlockPackMax> key;
    for (uint32_t k = 0; k < n; ++k) {
        const uint64_t v = centroid_key(centroids[prims[k]][axis], prims[k]);
        uint32_t j = k;
        for (; j > 0 && v < key[j - 1]; --j) key[j] = key[j - 1];
        key[j] = v;
    }
    for (uint32_t k = 0; k < n; ++k) out[k] = uint32_t(key[k]);
}

}  // namespace

Split block_split(BuildContext& ctx, const NodeRange& node, uint32_t depth) {
    const uint32_t n = node.count, block = std::max(1u, ctx.options.sah_block);
    const bool aligned = n > block;
    const auto& centroids = ctx.prims.centroids;
    const auto& bounds = ctx.prims.bounds;
    uint32_t* idx = ctx.indices.data() + node.first;
    const bool deep = depth >= kMaxSahDepth;  // past it only halving, which bounds the depth
    // A node of one block at most that may stay a leaf stays one: every split of it costs at
    // least kSahTraversalCost plus one block on each side's area share, so never less than the
    // leaf's one block (sah_split_cost; with zero area or NaN boxes more, or no decision), and the
    // sweep below would return the leaf anyway. Exact: the same tree, without three sorts.
    static_assert(kSahTraversalCost >= kSahIntersectionCost, "a split of one block must cost the leaf's block or more");
    if (n <= block && !deep && n <= uint32_t(ctx.options.max_leaf)) return {};

    // Each axis's order of the node's primitives (kBlockPackMax of them at most: on the stack).
    std::array<std::array<uint32_t, kBlockPackMax>, 3> order;
    std::array<float, kBlockPackMax> right_area;
    std::array<uint32_t, kBlockPackMax> right_count;
    float best_cost = kInfinity;
    int best_axis = -1;
    uint32_t best_left = 0;
    for (int axis = 0; axis < 3; ++axis) {
        uint32_t* o = order[size_t(axis)].data();
        sort_by_centroid(idx, n, centroids, axis, o);
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
