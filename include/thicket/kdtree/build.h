#pragma once
/// kD-tree construction. Builders see the primitives only through their bounds and a clipping
/// function (the exact bounds of the part of a primitive inside a box), so they are compiled
/// once and serve every primitive set.
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <span>
#include <string>

#include "thicket/core/tree_figures.h"
#include "thicket/kdtree/node.h"
#include "thicket/kdtree/sah.h"

namespace thicket {

enum class KdBuilder {
    Sah,     ///< Wald & Havran 2006: events sorted once, SAH sweep, perfect splits, O(N log N)
    Median,  ///< spatial median of the voxel's longest axis; the SAH only decides when to stop
};

struct KdBuildOptions {
    KdBuilder builder = KdBuilder::Sah;
    KdCostModel cost;
    /// Deepest leaf; 0 means the usual 8 + 1.3 log2 N (rounded), at most kKdMaxDepth.
    uint32_t max_depth = 0;
};

/// What builders see of the primitives.
struct KdBuildInput {
    std::span<const Aabb> bounds;
    /// Bounds of the part of primitive `prim` inside `box` (empty if none): exact for triangles,
    /// bounds intersected with box otherwise (clipped_bounds in primitive_set.h).
    std::function<Aabb(uint32_t prim, const Aabb& box)> clip;
};

/// The depth limit used for `primitives` primitives: options.max_depth, or 8 + 1.3 log2 N.
uint32_t kd_max_depth(const KdBuildOptions& options, size_t primitives);

/// Builds a kD-tree. Primitives with non-finite bounds can never be hit and are left out.
/// Throws Error if the tree would not fit the node's 30-bit fields.
KdTreeData build_kdtree(const KdBuildInput& input, const KdBuildOptions& options);

/// Figures of a built tree. Voxel areas are recomputed from the root voxel and the splits.
struct KdFigures : TreeFigures {
    /// The SAH sum with the builder's K_T and K_I (no empty-space bonus: it biases the choice of
    /// planes, it is not a cost of the tree); sah_cost is the figure every structure reports.
    double builder_cost = 0.0;
};
KdFigures kdtree_figures(const KdTreeData& tree, const KdCostModel& cost = {});

/// Checks the structural invariants (children after parents and in range, leaf ranges and
/// primitive indices in range, depth at most kKdMaxDepth, every node reachable once); throws
/// Error describing the first violation.
void validate_kdtree(const KdTreeData& tree, size_t primitive_count);
/// What traversal relies on (call after validate_kdtree): the root voxel holds every finite
/// primitive and every leaf lists each primitive the builders' classification sends to its cell
/// (src/kdtree/validate_coverage.cpp). Costs about one median build's classification pass.
void validate_kdtree_coverage(const KdTreeData& tree, const KdBuildInput& input);

/// Payload I/O for save_accel/load_accel; read_kdtree validates before returning.
void write_kdtree(std::ostream& out, const KdTreeData& tree);
KdTreeData read_kdtree(std::istream& in, size_t primitive_count);

}  // namespace thicket
