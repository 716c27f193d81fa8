#pragma once
/// BVH construction: a top-down skeleton shared by every builder, each builder choosing splits.
#include <cstdint>
#include <span>
#include <string>

#include "thicket/bvh/node.h"
#include "thicket/core/tree_figures.h"

namespace thicket {

enum class BvhBuilder { Midpoint, BinnedSah, SweepSah };

struct BvhBuildOptions {
    BvhBuilder builder = BvhBuilder::BinnedSah;
    int bins = 8;      ///< binned-sah: bins per axis (Wald 2007)
    int max_leaf = 8;  ///< a node with more primitives is always split
};

/// What builders see of the primitives: bounds and centroids, nothing else.
struct BuildPrimitives {
    std::span<const Aabb> bounds;
    std::span<const Vec3> centroids;
};

/// Builds a BVH over the primitives. Leaves are made when the SAH says splitting costs more
/// (kSahTraversalCost, kSahIntersectionCost) and the node holds at most max_leaf primitives.
BvhData build_bvh(const BuildPrimitives& prims, const BvhBuildOptions& options);

/// Figures of a built BVH (node boxes as stored).
using BvhFigures = TreeFigures;
BvhFigures bvh_figures(const BvhData& bvh);

/// Checks the structural invariants (indices in range, children after parents, depth bounded,
/// every primitive referenced once); throws Error describing the first violation.
void validate_bvh(const BvhData& bvh, size_t primitive_count);
/// What traversal relies on beyond structure (call after validate_bvh): every leaf box contains
/// its primitives' bounds, every interior box its children's, every child-order byte names real
/// axes. With these, culling a node whose box the ray misses never loses a hit.
void validate_bvh_bounds(const BvhData& bvh, std::span<const Aabb> prim_bounds);

/// Payload I/O for save_accel/load_accel; read_bvh validates before returning.
void write_bvh(std::ostream& out, const BvhData& bvh);
BvhData read_bvh(std::istream& in, size_t primitive_count);

}  // namespace thicket
