#pragma once
/// A structure drawn in its own terms (Accel::for_each_node): each node, cell or tetrahedron as
/// a box, a split plane clipped to its cell, an oriented box or a tetrahedron, at its depth.
/// `thicket explore` draws every structure from these alone, so a new structure is drawn by
/// implementing for_each_node, never by an edit to the explorer.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "thicket/core/aabb.h"

namespace thicket {

/// One node, cell or tetrahedron: its id (the one recorded steps name), depth (what the depth
/// slider walks through: DrawingLegend::depth_means), shape, and whether it holds primitives.
struct DrawnNode {
    enum class Shape : uint8_t {
        Box,      ///< `box`: a node's box or a cell
        Plane,    ///< `points`: a split plane clipped to its node's cell (a convex polygon, 3 or more
                  ///< corners); `box`: that cell when it is axis-aligned (kD-tree), else empty
        Oriented, ///< `points`: the centre, then the three half-axes (unit axis times half extent)
        Tetra,    ///< `points`: the four corners
    };
    uint32_t id = 0;
    uint32_t depth = 0;
    Aabb box;
    bool leaf = false;
    uint32_t prims = 0;  ///< primitives (references) a leaf or cell lists
    Shape shape = Shape::Box;
    std::vector<Vec3> points;
};

/// A node or cell drawn as its box.
inline DrawnNode drawn_box(uint32_t id, uint32_t depth, const Aabb& box, bool leaf, uint32_t prims) {
    return {id, depth, box, leaf, prims, DrawnNode::Shape::Box, {}};
}

/// What a structure's drawing shows, in words for the explorer's page.
struct DrawingLegend {
    std::string kind;         ///< "boxes", "planes and leaf cells", "cells", "oriented boxes", "tetrahedra"
    std::string depth_means;  ///< what the depth slider walks through
};

/// The callback Accel::for_each_node calls once per drawn node.
using DrawnNodeVisitor = std::function<void(const DrawnNode&)>;

}  // namespace thicket
