#pragma once
/// The BSP tree's node: an arbitrary plane (normal + offset) and two children, or a leaf's
/// range of primitive references. Plain arrays of indices, like the BVH.
#include <cstdint>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/aligned.h"

namespace thicket {

/// A plane {p : dot(normal, p) = offset}, normal of unit length. Its front side is where
/// dot(normal, p) > offset (the side the normal points to), its back side the other.
struct BspPlane {
    Vec3 normal;
    float offset = 0.0f;
};

/// Two nodes per 64-byte cache line. Interior: `plane` splits the cell, the back child is node
/// `index`, the front child `index + 1`. Leaf (kLeafBit set in `count`): the primitives are
/// refs[index .. index + (count & ~kLeafBit)).
struct alignas(32) BspNode {
    static constexpr uint32_t kLeafBit = 0x80000000u;

    BspPlane plane;
    uint32_t index = 0;
    uint32_t count = 0;
    /// The padding to 32 bytes, named so that it is zero: nodes are saved whole, and a saved
    /// structure must not depend on what the memory held before.
    uint32_t unused[2] = {0, 0};

    bool is_leaf() const { return (count & kLeafBit) != 0; }
    uint32_t leaf_size() const { return count & ~kLeafBit; }
};
static_assert(sizeof(BspNode) == 32, "a BSP node is 32 bytes: two per cache line");

/// Deepest tree the builder may make (the `max-depth` option's upper bound), and the traversal
/// stack that this depth guarantees not to overflow (one entry per level at most).
inline constexpr uint32_t kBspMaxDepth = 100;
inline constexpr uint32_t kBspStackSize = kBspMaxDepth + 2;

/// Relative width of the band around a split plane that both sides of it accept: the builder
/// counts a vertex within kBspPlaneBand/2 * scale of a plane as lying in it, and traversal widens
/// each plane crossing by kBspPlaneBand * (|origin| + 2 scale) / |n.d| (scale: the largest
/// coordinate magnitude of the scene), which also covers float rounding of the plane equation.
inline constexpr float kBspPlaneBand = 1e-6f;

/// A piece whose area is below this fraction of its triangle's area counts as a sliver.
inline constexpr double kBspSliverRatio = 1e-3;

/// What the builder measured about fragments ("splinters"). A fragment is a convex piece of an
/// original triangle (a box for non-triangle primitives) referenced by one leaf; a piece is a
/// fragment that is not its whole triangle.
struct BspSplinters {
    uint64_t fragments = 0;        ///< fragments referenced by leaves (= references)
    uint64_t splits = 0;           ///< fragments cut in two by a plane (each adds one fragment)
    uint64_t dropped = 0;          ///< halves of cut boxes the primitive does not reach (boxes only)
    uint64_t in_plane = 0;         ///< placements of a fragment lying in the chosen plane
    uint64_t split_triangles = 0;  ///< primitives that ended up in more than one fragment
    uint64_t pieces = 0;           ///< leaf fragments that are pieces of cut triangles
    uint64_t measured_pieces = 0;  ///< pieces of triangles with nonzero area (the next three figures)
    double smallest_area = 0.0;    ///< smallest such piece's area (0 when none)
    double smallest_ratio = 0.0;   ///< smallest such piece's area / its triangle's area (0 when none)
    uint64_t slivers = 0;          ///< such pieces under kBspSliverRatio of their triangle's area
    uint64_t depth_capped = 0;     ///< leaves made because max-depth was reached
    uint64_t budget_capped = 0;    ///< leaves made because every split would exceed the fragment budget
    uint64_t unsplittable = 0;     ///< leaves over max-leaf where no sampled plane separated anything
    bool polygons = false;         ///< fragments are triangle pieces (else boxes, no areas)
};

/// A built BSP tree: relocatable (indices only).
struct BspData {
    AlignedVector<BspNode, 64> nodes;  ///< root at 0; empty for an empty scene
    std::vector<uint32_t> refs;        ///< leaves' primitive ids
    Aabb bounds;                       ///< root cell: the scene's bounds
    float scale = 0.0f;                ///< largest coordinate magnitude of bounds (see kBspPlaneBand)
    BspSplinters splinters;
};

}  // namespace thicket
