#pragma once
// Each structure drawn in its own terms, one depth at a time, for the page's depth slider: BVH
// boxes, kD-tree and BSP split planes clipped to their cells, non-empty grid and octree cells,
// BIH intervals as boxes, OBB oriented boxes, tetrahedra by their distance from the surface.
// The geometry is read from the structures' own data (their read-only data() accessors), so
// nothing here changes how a structure is built or traversed.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"

namespace thicket::explore {

/// One thing drawn at the asked depth.
struct DrawnElement {
    enum class Shape : uint8_t {
        Box,      ///< `box`: a node's box or a cell
        Plane,    ///< `points`: a split plane clipped to its node's cell (a convex polygon, 3 or more corners)
        Oriented, ///< `points`: the centre, then the three half-axes (unit axis times half extent)
        Tetra,    ///< `points`: the four corners
    };
    Shape shape = Shape::Box;
    uint32_t id = 0;      ///< node, cell or tetrahedron index in the structure's own arrays
    bool leaf = false;
    uint32_t prims = 0;   ///< primitives a leaf or cell lists
    Aabb box;             ///< Box: the box; Plane: the axis-aligned cell clipping it, when it is one (kdtree)
    std::vector<Vec3> points;
};

/// A structure's drawing at one depth.
struct Drawing {
    std::string kind;       ///< what is drawn: "boxes", "planes and leaf cells", "cells", "oriented boxes", "tetrahedra"
    std::string depth_means;///< what the depth slider walks through, in words
    uint32_t max_depth = 0; ///< deepest level that has anything to draw
    std::vector<DrawnElement> elements;  ///< everything drawn at the asked depth, in the structure's order
};

/// The drawing of `accel` at `depth`, or nothing when the structure does not draw itself (brute
/// force; a structure wrapped for instancing). Structures that name their nodes for recorded
/// steps (Accel::for_each_node: bvh, grid) are drawn with those ids, so a traced step's node is
/// the drawn one.
std::optional<Drawing> draw_structure(const Accel& accel, uint32_t depth);

/// Whether draw_structure answers for `accel` (cheap: no geometry is made).
bool draws_itself(const Accel& accel);

}  // namespace thicket::explore
