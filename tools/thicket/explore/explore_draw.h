#pragma once
// A structure's drawing one depth at a time, for the page's depth slider. Every structure draws
// itself (Accel::for_each_node, core/drawn_node.h: BVH boxes, kD-tree and BSP split planes clipped
// to their cells, grid and octree cells, BIH intervals as boxes, OBB oriented boxes, tetrahedra by
// their distance from the surface); this keeps one level of what it draws. Nothing here knows
// which structure it draws.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"

namespace thicket::explore {

/// A structure's drawing at one depth.
struct Drawing {
    DrawingLegend legend;   ///< what is drawn and what the depth slider walks through
    uint32_t max_depth = 0; ///< deepest level that has anything to draw
    std::vector<DrawnNode> elements;  ///< everything drawn at the asked depth, in the structure's order
};

/// The drawing of `accel` at `depth`, or nothing when the structure does not draw itself (brute
/// force; instances). The ids are those recorded steps name, so a traced step's node is the drawn one.
std::optional<Drawing> draw_structure(const Accel& accel, uint32_t depth);

/// Whether draw_structure answers for `accel` (cheap: no geometry is made).
inline bool draws_itself(const Accel& accel) { return accel.drawing_legend().has_value(); }

}  // namespace thicket::explore
