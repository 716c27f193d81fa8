#pragma once
/// The octree's 8-byte node, its implicit cell boxes, and the flat arrays an octree is made of.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "thicket/core/aabb.h"

namespace thicket {

/// An inner node's eight children are stored consecutively from `index`; child c is the upper
/// half of its parent on x, y, z where bit 0, 1, 2 of c is set. A leaf references the primitive
/// ids refs[index, index + count) (a primitive overlapping several cells is referenced by each).
struct OctreeNode {
    static constexpr uint32_t kInner = 0xFFFFFFFFu;

    uint32_t index = 0;
    uint32_t count = 0;  ///< kInner for an inner node

    bool is_leaf() const { return count != kInner; }
};
static_assert(sizeof(OctreeNode) == 8, "an octree node is two 32-bit words");

/// The plane where a cell's halves meet: the middle of [lo, hi], never outside it. Builder and
/// traversals compute every cell's planes with this one function from the same root box, so a
/// plane shared by two cells is the same float wherever it is computed.
inline float octree_mid(float lo, float hi) { return std::clamp(0.5f * lo + 0.5f * hi, lo, hi); }

/// Box of child c of the cell `box`.
inline Aabb octree_child_box(const Aabb& box, int c) {
    Aabb child = box;
    for (int a = 0; a < 3; ++a) {
        const float mid = octree_mid(box.min[a], box.max[a]);
        ((c >> a) & 1 ? child.min : child.max)[a] = mid;
    }
    return child;
}

/// Deepest tree the builder makes (the max-depth option's upper bound).
inline constexpr uint32_t kOctreeMaxDepth = 16;
/// Most nodes a tree may have (node indices are 32-bit, kInner reserved).
inline constexpr size_t kOctreeMaxNodes = size_t(1) << 31;

/// A built octree: relocatable (indices only).
struct OctreeData {
    std::vector<OctreeNode> nodes;  ///< root at 0; empty for an empty scene
    std::vector<uint32_t> refs;     ///< the leaves' primitive ids, leaf by leaf, ascending in each
    Aabb root;                      ///< the root cell: a cube enclosing every primitive
};

}  // namespace thicket
