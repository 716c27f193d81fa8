// The grids' drawings (grid/draw.h).
#include "thicket/grid/draw.h"

namespace thicket {

void draw_nodes(const GridData& g, const DrawnNodeVisitor& visit) {
    const GridFrame& f = g.frame;
    if (g.lists.cells() == 0) return;
    f.for_each_cell([&](const uint32_t cell[3], uint32_t i) {
        if (const uint32_t n = g.lists.count(i)) visit(drawn_box(i, 0, f.cell_box(cell), true, n));
    });
}

DrawingLegend draw_legend(const GridData&) { return {"cells", "one level: the grid's non-empty cells"}; }

void draw_nodes(const Grid2Data& g, const DrawnNodeVisitor& visit) {
    const GridFrame& f = g.frame;
    if (g.top.empty()) return;
    f.for_each_cell([&](const uint32_t cell[3], uint32_t t) {
        const TopCell& tc = g.top[t];
        if (tc.empty()) return;
        const GridFrame sub = g.sub_frame(cell, tc);
        uint32_t refs = 0;
        for (uint32_t k = 0; k < sub.cells(); ++k) refs += g.leaves.count(tc.first_leaf + k);
        if (refs == 0) return;
        visit(drawn_box(t, 0, f.cell_box(cell), false, refs));
        sub.for_each_cell([&](const uint32_t sub_cell[3], uint32_t k) {
            const uint32_t l = tc.first_leaf + k;
            if (const uint32_t n = g.leaves.count(l)) visit(drawn_box(l, 1, sub.cell_box(sub_cell), true, n));
        });
    });
}

DrawingLegend draw_legend(const Grid2Data&) {
    return {"cells", "0: the top grid's non-empty cells; 1: the non-empty cells of their sub-grids"};
}

}  // namespace thicket
