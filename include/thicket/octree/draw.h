#pragma once
/// The octree as `thicket explore` draws it (Accel::for_each_node; core/drawn_node.h).
#include "thicket/core/drawn_node.h"
#include "thicket/octree/node.h"

namespace thicket {

/// Calls `visit` for every inner cell and every non-empty leaf cell, parents first. Ids are node
/// indices.
void draw_nodes(const OctreeData& octree, const DrawnNodeVisitor& visit);
/// What draw_nodes' cells and depths mean.
DrawingLegend draw_legend(const OctreeData& octree);

}  // namespace thicket
