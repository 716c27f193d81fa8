#pragma once
/// Figures of grids for AccelStats: cells, references, empty cells, the expected-cost estimate.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "thicket/grid/cells.h"
#include "thicket/grid/frame.h"
#include "thicket/grid/grid2_build.h"

namespace thicket {

/// Cost estimate of cells in the SAH's terms: sum over cells of A(cell)/A(root) * (C_trav +
/// C_isect * references). A(cell)/A(root) is the chance that a ray through the root box pierces
/// the cell, so the sum of those ratios is the expected number of cells a ray walks (no early
/// stop, no mailbox). A root of zero area (all primitives on a line or a point) counts the
/// average cell once.
struct CellFigures {
    size_t cells = 0;
    size_t empty = 0;
    size_t refs = 0;
    size_t max_refs = 0;
    double cost = 0.0;  ///< in units of the root's area: sum A(cell)/A(root) * (C_trav + C_isect * refs)
};

/// Figures of the cells [first, first + f.cells()) of `lists`; `root_area` is the area costs are
/// relative to.
CellFigures cell_figures(const GridFrame& f, const CellLists& lists, size_t first, double root_area);

/// Two-level grid: the top cells (each walked costs C_trav) and all sub-grid cells together.
struct Grid2Figures {
    size_t top_cells = 0;
    size_t top_empty = 0;
    CellFigures leaf;  ///< summed over every sub-grid; leaf.cost is the cost of the sub-grid cells
    double cost = 0.0; ///< top cells' traversal cost plus leaf.cost
};
Grid2Figures grid2_figures(const Grid2Data& g);

/// "12.3%" style, for stats.extra.
std::string percent(double part, double whole);
/// Fixed-point with `digits` decimals.
std::string fixed(double v, int digits);

}  // namespace thicket
