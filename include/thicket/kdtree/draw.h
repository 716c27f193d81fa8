#pragma once
/// The kD-tree as `thicket explore` draws it (Accel::for_each_node; core/drawn_node.h).
#include "thicket/core/drawn_node.h"
#include "thicket/kdtree/node.h"

namespace thicket {

/// Calls `visit` for every node but the empty leaves, parents first: an inner node is its split
/// plane clipped to its cell (a rectangle, the cell in DrawnNode::box), a non-empty leaf its cell.
/// Ids are node indices.
void draw_nodes(const KdTreeData& kd, const DrawnNodeVisitor& visit);
/// What draw_nodes' planes, cells and depths mean.
DrawingLegend draw_legend(const KdTreeData& kd);

}  // namespace thicket
