#pragma once
/// The BVH's nodes as `thicket explore` draws them and recorded steps name them
/// (Accel::for_each_node; core/drawn_node.h).
#include "thicket/bvh/node.h"
#include "thicket/core/drawn_node.h"

namespace thicket {

/// Calls `visit` for every node reachable from the root (none for an empty BVH), parents before
/// children; DrawnNode::id is the node-pool index the traversal records.
void draw_nodes(const BvhData& bvh, const DrawnNodeVisitor& visit);
/// What draw_nodes' boxes and depths mean (also bvh8's).
DrawingLegend draw_legend(const BvhData& bvh);

}  // namespace thicket
