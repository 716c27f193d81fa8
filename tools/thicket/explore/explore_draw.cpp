// One level of a structure's own drawing (explore_draw.h).
#include "explore_draw.h"

#include <algorithm>
#include <utility>

namespace thicket::explore {

std::optional<Drawing> draw_structure(const Accel& accel, uint32_t depth) {
    std::optional<DrawingLegend> legend = accel.drawing_legend();
    if (!legend) return std::nullopt;
    Drawing d{std::move(*legend), 0, {}};
    accel.for_each_node([&](const DrawnNode& n) {
        d.max_depth = std::max(d.max_depth, n.depth);
        // A plane that misses its cell (DrawnNode::Shape::Plane) counts for its level, drawn as nothing.
        if (n.depth == depth && (n.shape != DrawnNode::Shape::Plane || n.points.size() >= 3)) d.elements.push_back(n);
    });
    return d;
}

}  // namespace thicket::explore
