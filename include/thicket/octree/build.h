#pragma once
/// Adaptive octree construction (Glassner 1984) and its figures.
#include <cstddef>
#include <functional>
#include <span>

#include "thicket/core/tree_figures.h"
#include "thicket/octree/node.h"

namespace thicket {

struct OctreeBuildOptions {
    int leaf_size = 8;   ///< a cell holding more primitives is split (while depth < max_depth)
    int max_depth = 10;  ///< deepest level; the root is level 0
};

/// Bounds of the part of primitive i inside a box (empty if none): clipped_bounds().
using OctreeClip = std::function<Aabb(uint32_t, const Aabb&)>;

/// Builds an octree over primitives with the given bounds. The root is a cube around them; a
/// cell is split into its eight octants while it holds more than leaf_size primitives, is less
/// than max_depth deep, and splitting separates something: a split whose non-empty children (at
/// least two) would each hold every primitive of the cell is not made. A primitive goes to every
/// child its clipped part touches (closed cells: one lying in a plane between two children goes
/// to both). The build also stops splitting once the leaves would hold more than
/// kOctreeReferenceBudget references per primitive, so memory stays bounded on any input.
OctreeData build_octree(std::span<const Aabb> bounds, const OctreeClip& clip, const OctreeBuildOptions& options);

/// References per primitive (plus a fixed allowance for tiny scenes) past which no cell is split.
inline constexpr size_t kOctreeReferenceBudget = 8;

/// Figures of a built octree. sah_cost weighs every cell by its area relative to the root's,
/// with kSahTraversalCost per inner cell and kSahIntersectionCost per reference in a leaf.
using OctreeFigures = TreeFigures;
OctreeFigures octree_figures(const OctreeData& tree);

}  // namespace thicket
