#pragma once
/// Adaptive octree construction (Glassner 1984) and its figures.
#include <cstddef>
#include <functional>
#include <iosfwd>
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
/// Most references a built tree over `primitives` primitives holds, in its leaves and in any one
/// level of its cells.
inline size_t octree_reference_budget(size_t primitives) { return kOctreeReferenceBudget * primitives + 4096; }

/// The root cell over primitives whose bounds are `scene`: Glassner's cells are cubes, so the
/// root is the cube on the scene's lowest corner whose side is its largest extent.
Aabb octree_root_cube(const Aabb& scene);

/// Checks the structure (children after their parent and in range, every node reached once,
/// depth at most kOctreeMaxDepth, leaf ranges and primitive ids in range); throws Error
/// describing the first violation.
void validate_octree(const OctreeData& tree, size_t primitive_count);
/// What traversal relies on (call after validate_octree): the root is the builder's cube around
/// the primitives, and the builder's distribution of each cell's primitives into its children,
/// replayed over the stored splits, finds every leaf listing every primitive whose part reaches
/// its cell (src/octree/validate_coverage.cpp). Costs about what the build's distribution costs.
void validate_octree_coverage(const OctreeData& tree, std::span<const Aabb> bounds, const OctreeClip& clip);

/// Payload I/O for save_accel/load_accel; read_octree validates the structure before returning.
void write_octree(std::ostream& out, const OctreeData& tree);
OctreeData read_octree(std::istream& in, size_t primitive_count);

/// Figures of a built octree. sah_cost weighs every cell by its area relative to the root's,
/// with kSahTraversalCost per inner cell and kSahIntersectionCost per reference in a leaf.
using OctreeFigures = TreeFigures;
OctreeFigures octree_figures(const OctreeData& tree);

}  // namespace thicket
