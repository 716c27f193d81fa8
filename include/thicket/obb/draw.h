#pragma once
/// The oriented-box hierarchy as `thicket explore` draws it (Accel::for_each_node; core/drawn_node.h).
#include "thicket/core/drawn_node.h"
#include "thicket/obb/node.h"

namespace thicket {

/// Calls `visit` for every node, parents first: its oriented box (DrawnNode::Shape::Oriented). Ids
/// are node indices.
void draw_nodes(const ObbData& obb, const DrawnNodeVisitor& visit);
/// What draw_nodes' boxes and depths mean.
DrawingLegend draw_legend(const ObbData& obb);

}  // namespace thicket
