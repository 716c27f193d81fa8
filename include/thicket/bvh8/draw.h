#pragma once
/// bvh8's nodes as `thicket explore` draws them and its recorded steps name them (Accel's
/// for_each_node and intersect with a TraversalRecorder; core/traversal_record.h). Baseline code:
/// the kernels reach the recorder only through the StepSink's function pointers (node.h).
#include <cstddef>

#include "thicket/bvh8/node.h"
#include "thicket/core/drawn_node.h"
#include "thicket/core/traversal_record.h"

namespace thicket::bvh8 {

/// Calls `visit` for the root and every node and leaf below it in pre-order, children in lane
/// order (so a node's parent is the last node listed one level up; none when node_count is 0). Ids: a node's index in the node array; a leaf's is
/// node_count plus its first block (block leaves) or first id (callback leaves), unique because
/// leaves never share storage. A child's box is its parent's lane box as the kernels test it
/// (decoded for compressed nodes); the root's is the union of its lanes. DrawnNode::prims counts a
/// leaf's triangles (valid block lanes) or ids.
void for_each_node(const TraceContext& ctx, size_t node_count, bool blocks, const DrawnNodeVisitor& visit);
/// What for_each_node's boxes and depths mean (a binary BVH's words: levels of boxes).
DrawingLegend draw_legend();

/// A StepSink that appends to `recorder` (TraversalRecorder's record_* members), ids numbered
/// as for_each_node numbers them for a tree of node_count nodes.
StepSink step_sink(TraversalRecorder& recorder, size_t node_count);

}  // namespace thicket::bvh8
