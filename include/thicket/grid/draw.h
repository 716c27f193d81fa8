#pragma once
/// The grids as `thicket explore` draws them (Accel::for_each_node; core/drawn_node.h).
#include "thicket/core/drawn_node.h"
#include "thicket/grid/grid2_build.h"
#include "thicket/grid/grid_build.h"

namespace thicket {

/// Calls `visit` for every non-empty cell, at depth 0; ids are the linear cell indices the walk
/// records.
void draw_nodes(const GridData& grid, const DrawnNodeVisitor& visit);
/// What draw_nodes' cells mean.
DrawingLegend draw_legend(const GridData& grid);

/// Calls `visit` for every non-empty top cell (depth 0, its id the top cell's index) and, after
/// each, the non-empty cells of its sub-grid (depth 1, ids their index in the shared cell lists).
void draw_nodes(const Grid2Data& grid, const DrawnNodeVisitor& visit);
/// What draw_nodes' two levels mean.
DrawingLegend draw_legend(const Grid2Data& grid);

}  // namespace thicket
