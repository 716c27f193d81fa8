#pragma once
/// The lecture's 32-byte BVH node and the flat arrays a BVH is made of.
#include <cstdint>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/aligned.h"

namespace thicket {

/// Two float nodes per 64-byte cache line (one double node per line). A node is a leaf iff
/// count > 0: then its primitives are prim_indices[leftFirst .. leftFirst+count). Otherwise its
/// children are nodes leftFirst and leftFirst+1 (right = left + 1, so one index serves both).
template <class S>
struct alignas(sizeof(S) == 4 ? 32 : 64) BvhNodeT {
    Vec3T<S> aabbMin;
    uint32_t leftFirst = 0;
    Vec3T<S> aabbMax;
    uint32_t count = 0;

    bool is_leaf() const { return count > 0; }
    AabbT<S> bounds() const { return {aabbMin, aabbMax}; }
};
using BvhNode = BvhNodeT<float>;
using BvhNodeD = BvhNodeT<double>;  ///< the `precision=double` BVH's node
static_assert(sizeof(BvhNode) == 32, "the lecture's node is 32 bytes: two per cache line");
static_assert(sizeof(BvhNodeD) == 64, "one double node per cache line");

/// Per interior node, what the ordered traversals need beside the 32-byte node (one byte, kept
/// apart so the node stays 32 bytes): bits 0-1 the split axis, bits 2-3 the axis of widest
/// child-centroid separation, bit 4 set when on that axis the left child's centroid is the higher
/// one, bit 5 set when on the split axis it is (a refit after a mirror, a bottom-up builder: the
/// left child no longer holds the lower side, and the ordered-axis traversal must know).
struct ChildOrder {
    static uint8_t pack(int split_axis, int centroid_axis, bool left_is_higher, bool split_left_higher = false) {
        return uint8_t(split_axis | (centroid_axis << 2) | (left_is_higher ? 16 : 0) | (split_left_higher ? 32 : 0));
    }
    static int split_axis(uint8_t b) { return b & 3; }
    static int centroid_axis(uint8_t b) { return (b >> 2) & 3; }
    static bool left_is_higher(uint8_t b) { return (b & 16) != 0; }
    static bool split_left_higher(uint8_t b) { return (b & 32) != 0; }
    /// The byte of an interior node whose split axis is `split_axis`, every other bit from its
    /// children's boxes' centres (the build's compute_child_order and every refit).
    static uint8_t from_children(int split_axis, const Aabb& left, const Aabb& right) {
        const Vec3 cl = left.center(), cr = right.center();
        const int axis = max_axis(abs(cr - cl));
        return pack(split_axis, axis, cl[axis] > cr[axis], cl[split_axis] > cr[split_axis]);
    }
    /// Every bit a valid byte may set.
    static constexpr uint8_t kBits = 64;
};

/// Deepest tree a builder makes; past kMaxSahDepth builders fall back to median splits, which
/// halve the count, so depth stays below kMaxDepth and fixed traversal stacks cannot overflow.
inline constexpr uint32_t kMaxSahDepth = 64;
inline constexpr uint32_t kMaxDepth = 100;
inline constexpr uint32_t kTraversalStackSize = 128;

/// A built BVH: relocatable (indices only, no pointers), hence serializable as is. The double
/// one (BvhDataD) holds the float builder's topology, leaf order and child order bytes, with each
/// node's box the union of its triangles' double boxes (bvh/bvh_double.h).
template <class S>
struct BvhDataT {
    using Node = BvhNodeT<S>;
    using Scalar = S;
    AlignedVector<Node, 64> nodes;     ///< pool of 2N nodes: root at 0, 1 unused (cache alignment)
    std::vector<uint32_t> prim_indices;///< partitioned in place by the builder
    std::vector<uint8_t> child_order;  ///< ChildOrder byte per node (interior nodes only meaningful)
    uint32_t nodes_used = 0;           ///< 0 for an empty scene
};
using BvhData = BvhDataT<float>;
using BvhDataD = BvhDataT<double>;

}  // namespace thicket
