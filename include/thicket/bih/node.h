#pragma once
/// The bounding interval hierarchy's 12-byte node (Wächter & Keller 2006) and the flat arrays a
/// BIH is made of.
#include <bit>
#include <cstdint>
#include <vector>

#include "thicket/core/aabb.h"

namespace thicket {

/// 12 bytes, as in the paper. `header` bits 0-1 hold the split axis (0, 1, 2) or 3 for a leaf;
/// bits 2-31 the index of the left child (the right child follows it) or of the leaf's first
/// entry in the primitive index array. An inner node's two words are the clip planes as float
/// bits: the highest coordinate of the left child's primitives and the lowest of the right
/// child's on the split axis (the intervals may overlap or leave a gap). A leaf's first word is
/// its primitive count. An empty child is a leaf of count 0 whose clip plane is -inf (left) or
/// +inf (right), so traversal never enters it.
struct BihNode {
    uint32_t header = 3;
    uint32_t word[2] = {0, 0};

    static constexpr uint32_t kLeaf = 3;

    static BihNode inner(int axis, uint32_t left_child, float left_max, float right_min) {
        return {uint32_t(axis) | (left_child << 2), {std::bit_cast<uint32_t>(left_max), std::bit_cast<uint32_t>(right_min)}};
    }
    static BihNode leaf(uint32_t first, uint32_t count) { return {kLeaf | (first << 2), {count, 0}}; }

    bool is_leaf() const { return (header & 3) == kLeaf; }
    int axis() const { return int(header & 3); }
    /// Left child (inner node) or first primitive entry (leaf).
    uint32_t index() const { return header >> 2; }
    float left_max() const { return std::bit_cast<float>(word[0]); }
    float right_min() const { return std::bit_cast<float>(word[1]); }
    uint32_t count() const { return word[0]; }
};
static_assert(sizeof(BihNode) == 12, "the paper's node: 4 bytes of axis and index, two 4-byte planes");

/// Largest node or primitive index the 30-bit field holds.
inline constexpr uint32_t kBihMaxIndex = (1u << 30) - 1;
/// Depth bound: past kBihMaxSpatialDepth the builder splits by count, which halves the range,
/// so depth stays below kBihMaxDepth and the fixed traversal stack cannot overflow.
inline constexpr uint32_t kBihMaxSpatialDepth = 64;
inline constexpr uint32_t kBihMaxDepth = kBihMaxSpatialDepth + 33;
inline constexpr uint32_t kBihStackSize = 128;

/// A built BIH: relocatable (indices only).
struct BihData {
    std::vector<BihNode> nodes;          ///< root at 0; empty for an empty scene
    std::vector<uint32_t> prim_indices;  ///< partitioned in place by the builder
    Aabb bounds;                         ///< of every primitive: the root's implicit box
};

}  // namespace thicket
