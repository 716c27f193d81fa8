#pragma once
/// The BSP tree as `thicket explore` draws it (Accel::for_each_node; core/drawn_node.h).
#include "thicket/core/drawn_node.h"
#include "thicket/bsp/node.h"

namespace thicket {

/// Calls `visit` for every inner node, parents first: its plane clipped to its cell, the root box
/// cut by every ancestor's plane on the side the node lies. A plane that misses its cell (rounding
/// at a sliver) has fewer than 3 points and is drawn as nothing. Ids are node indices.
void draw_nodes(const BspData& bsp, const DrawnNodeVisitor& visit);
/// What draw_nodes' planes and depths mean.
DrawingLegend draw_legend(const BspData& bsp);

}  // namespace thicket
