#pragma once
/// The tetrahedral mesh as `thicket explore` draws it (Accel::for_each_node; core/drawn_node.h).
#include "thicket/core/drawn_node.h"
#include "thicket/tetra/mesh.h"

namespace thicket {

/// Calls `visit` for every tetrahedron reachable across faces from one with a face on the scene's
/// surface, in index order, at depth = its steps from the nearest such one (so depth 0 hugs the
/// mesh and deeper levels fill the empty space a ray walks through; a mesh with no surface face is
/// all depth 0). Ids are tetrahedron indices, the ones the walk records.
void draw_nodes(const TetraData& tetra, const DrawnNodeVisitor& visit);
/// What draw_nodes' tetrahedra and depths mean.
DrawingLegend draw_legend(const TetraData& tetra);

}  // namespace thicket
