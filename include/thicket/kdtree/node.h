#pragma once
/// The kD-tree's 8-byte node (the layout of pbrt and Wald's thesis) and the flat arrays a tree is
/// made of. Nodes are stored depth first: the below child of an interior node directly follows
/// it, so only the above child's index is stored.
#include <bit>
#include <cstdint>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/aligned.h"

namespace thicket {

/// Interior: `word` holds the split position (float bits), `bits` the axis (low 2 bits) and the
/// above child's index (high 30 bits). Leaf: `word` is the first entry in the primitive index
/// list, `bits` holds 3 (low 2 bits) and the number of entries (high 30 bits).
struct KdNode {
    uint32_t word = 0;
    uint32_t bits = 3;

    static KdNode interior(int axis, float split, uint32_t above) {
        return {std::bit_cast<uint32_t>(split), (above << 2) | uint32_t(axis)};
    }
    static KdNode leaf(uint32_t first, uint32_t count) { return {first, (count << 2) | 3u}; }

    bool is_leaf() const { return (bits & 3u) == 3u; }
    int axis() const { return int(bits & 3u); }
    float split() const { return std::bit_cast<float>(word); }
    uint32_t above() const { return bits >> 2; }  ///< the below child is this node's index + 1
    uint32_t first() const { return word; }
    uint32_t count() const { return bits >> 2; }
};
static_assert(sizeof(KdNode) == 8, "kD-tree nodes are 8 bytes: eight per cache line");

/// Largest node index and leaf size the 30-bit fields hold; builders throw Error beyond.
inline constexpr uint32_t kKdMaxField = (1u << 30) - 1;
/// Deepest tree any builder makes or a loaded file may hold; traversal stacks are sized by it.
inline constexpr uint32_t kKdMaxDepth = 60;
inline constexpr uint32_t kKdStackSize = kKdMaxDepth + 4;

/// A built kD-tree: relocatable (indices only), hence saved as is.
struct KdTreeData {
    AlignedVector<KdNode, 64> nodes;     ///< empty for an empty scene; root at 0
    std::vector<uint32_t> prim_indices;  ///< the leaves' primitive lists, one after another
    Aabb bounds;                         ///< the root voxel: bounds of every primitive in the tree
    uint32_t primitives = 0;             ///< primitives of the set the tree was built over
};

}  // namespace thicket
