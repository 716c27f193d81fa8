#pragma once
/// The BIH as `thicket explore` draws it (Accel::for_each_node; core/drawn_node.h).
#include "thicket/core/drawn_node.h"
#include "thicket/bih/node.h"

namespace thicket {

/// Calls `visit` for every node with a box, parents first: the root box cut by its ancestors' clip
/// planes. A child whose interval is empty (the -inf/+inf planes of an empty side) has no box and
/// is left out with what lies below it. Ids are node indices.
void draw_nodes(const BihData& bih, const DrawnNodeVisitor& visit);
/// What draw_nodes' boxes and depths mean.
DrawingLegend draw_legend(const BihData& bih);

}  // namespace thicket
