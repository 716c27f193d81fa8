#pragma once
/// Building the 8-wide tree: a binary BVH from any `bvh` builder, collapsed into 8-wide nodes
/// whose leaves some leaf storage (blocks.h, or primitive ids) places. Refit (new vertices, the
/// same topology) sits next to this: refit.h, a backward pass over Tree::nodes (children come
/// after their parents) recomputing each lane's box (docs/bvh8.md, "Files").
#include <cstdint>
#include <functional>
#include <vector>

#include "thicket/bvh/build.h"
#include "thicket/bvh/node.h"
#include "thicket/bvh8/node.h"
#include "thicket/core/aligned.h"
#include "thicket/prims/primitive_set.h"

namespace thicket::bvh8 {

/// Where a binary leaf went: its first block (or id) and size in the leaf storage; size 0 drops
/// the leaf (all its triangles degenerate).
struct LeafPlacement {
    uint32_t first = 0;
    uint32_t size = 0;
};
/// Stores the primitives prim_indices[first, first + count) of a binary leaf.
using LeafEmitter = std::function<LeafPlacement(uint32_t first, uint32_t count)>;

/// The nodes of an 8-wide tree and the figures of its build.
struct Tree {
    AlignedVector<Node, 64> nodes;  ///< root at 0, depth-first; empty for an empty scene
    Aabb bounds;                    ///< of every primitive (degenerate ones included)
    size_t leaves = 0;
    size_t max_depth = 0;           ///< levels of 8-wide nodes, the leaves' level included
    double sah_cost = 0.0;          ///< Thicket's metric (kSahTraversalCost, kSahIntersectionCost)
    double embree_sah_cost = 0.0;   ///< Embree's: (sum node areas + sum leaf area x 4-blocks) / root area
};

/// A tree another builder made (Embree's, through rtcBuildBVH: bvh8/foreign_tree.h), up to 8
/// children per node, written into 8-wide nodes as it is by write_wide_tree.
struct WideTree {
    struct Item {
        Aabb box;
        uint32_t first = 0, count = 0;  ///< a node's children[first..+count), a leaf's prims[first..+count)
        bool leaf = false;
    };
    std::vector<Item> items;          ///< items[0] is the root; empty for an empty scene
    std::vector<uint32_t> children;   ///< indices into items
    std::vector<uint32_t> prims;      ///< primitive ids (a spatial split may list one in several leaves)
};

/// The binary BVH over every primitive of `prims` that the collapse starts from: their bounds
/// gathered on options.threads threads and binned by the boxes' centres (as Embree's builders
/// bin: a lower SAH than the vertex centroid on every shared scene, BENCHMARKS.md "Tree against
/// kernel"), spatial splits (sbvh) clipping them exactly where the set can (clipped_bounds).
template <PrimitiveSet P>
BvhData build_binary(const P& prims, const BvhBuildOptions& options) {
    std::vector<Aabb> bounds;
    std::vector<Vec3> centroids;
    // primitive_boxes stores bounds[i] before it asks for centroid i: the centre reads it.
    primitive_boxes(
        uint32_t(prims.size()), options.threads, bounds, centroids, [&](uint32_t i) { return prims.bounds(i); },
        [&](uint32_t i) { return bounds[i].center(); });
    const ClipFunction clip = [&prims](uint32_t i, const Aabb& box) { return clipped_bounds(prims, i, box); };
    return build_bvh({bounds, centroids, clip}, options);
}

/// Collapses `binary` greedily: a node's children start as its two binary children, and the
/// interior child of largest surface area is replaced by its own two until there are 8 or
/// only leaves. Every binary leaf, and every subtree of at most `merge_below` primitives,
/// becomes one lane, stored by `emit`.
Tree collapse(const BvhData& binary, const LeafEmitter& emit, uint32_t merge_below);

/// The 4-triangle blocks collapse(binary, emit, merge_below) stores when every primitive is
/// packed: ceil(n / 4) per lane's leaf of n. An upper bound when the packing drops degenerate or
/// repeated triangles; so the blocks are reserved once, neither 4x too many nor copied to fit.
size_t block_count(const BvhData& binary, uint32_t merge_below);

/// The 8-wide tree of `wide` as it is: one node per interior item, its children in their order,
/// each leaf item one lane stored by emit(first, count) (prims[first .. first + count)).
Tree write_wide_tree(const WideTree& wide, const LeafEmitter& emit);

/// The 4-triangle blocks write_wide_tree stores when every primitive is packed (as block_count).
size_t block_count(const WideTree& wide);

/// Checks what the kernels rely on: child indices in range and after their parent (no cycle),
/// leaves within `leaf_slots`, empty lanes inverted. Throws Error naming the first violation.
void validate_tree(const Tree& tree, size_t leaf_slots);

}  // namespace thicket::bvh8
