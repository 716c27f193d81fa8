#include "thicket/grid/grid_stats.h"

#include <algorithm>
#include <cstdio>

#include "thicket/core/sah.h"

namespace thicket {

CellFigures cell_figures(const GridFrame& f, const CellLists& lists, size_t first, double root_area) {
    CellFigures r;
    r.cells = f.cells();
    for (size_t c = first; c < first + r.cells; ++c) {
        const size_t n = lists.count(c);
        r.refs += n;
        r.empty += n == 0;
        r.max_refs = std::max(r.max_refs, n);
    }
    // Every cell of a frame has the same area, so the sum over cells factors out.
    const Aabb cell = f.cell_box(0, 0, 0);
    const double ratio = root_area > 0.0 ? double(cell.area()) / root_area : 1.0 / double(r.cells);
    r.cost = ratio * (kSahTraversalCost * double(r.cells) + kSahIntersectionCost * double(r.refs));
    return r;
}

Grid2Figures grid2_figures(const Grid2Data& g) {
    Grid2Figures r;
    const double root_area = g.box.area();
    r.top_cells = g.frame.cells();
    const double top_ratio = root_area > 0.0 ? double(g.frame.cell_box(0, 0, 0).area()) / root_area
                                             : 1.0 / double(r.top_cells);
    r.cost = top_ratio * kSahTraversalCost * double(r.top_cells);
    g.frame.for_each_cell([&](const uint32_t cell[3], uint32_t c) {
        const TopCell& tc = g.top[c];
        if (tc.empty()) {
            ++r.top_empty;
            return;
        }
        CellFigures f = cell_figures(g.sub_frame(cell, tc), g.leaves, tc.first_leaf, root_area);
        // A root of zero area weighs each top cell equally (and its sub-cells within it).
        if (!(root_area > 0.0)) f.cost /= double(r.top_cells);
        r.leaf.cells += f.cells;
        r.leaf.empty += f.empty;
        r.leaf.refs += f.refs;
        r.leaf.max_refs = std::max(r.leaf.max_refs, f.max_refs);
        r.leaf.cost += f.cost;
    });
    r.cost += r.leaf.cost;
    return r;
}

std::string percent(double part, double whole) { return fixed(whole > 0.0 ? 100.0 * part / whole : 0.0, 1) + "%"; }

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), "%.*f", digits, v);
    return buf;
}

}  // namespace thicket
