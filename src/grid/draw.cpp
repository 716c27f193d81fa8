// The grids' drawings (grid/draw.h).
#include "thicket/grid/draw.h"

namespace thicket {

void draw_nodes(const GridData& g, const DrawnNodeVisitor& visit) {
    const GridFrame& f = g.frame;
    if (g.lists.cells() == 0) return;
    for (uint32_t z = 0; z < f.res[2]; ++z)
        for (uint32_t y = 0; y < f.res[1]; ++y)
            for (uint32_t x = 0; x < f.res[0]; ++x) {
                const uint32_t i = f.index(x, y, z), n = g.lists.count(i);
                if (n) visit(drawn_box(i, 0, f.cell_box(x, y, z), true, n));
            }
}

DrawingLegend draw_legend(const GridData&) { return {"cells", "one level: the grid's non-empty cells"}; }

void draw_nodes(const Grid2Data& g, const DrawnNodeVisitor& visit) {
    const GridFrame& f = g.frame;
    if (g.top.empty()) return;
    for (uint32_t z = 0; z < f.res[2]; ++z)
        for (uint32_t y = 0; y < f.res[1]; ++y)
            for (uint32_t x = 0; x < f.res[0]; ++x) {
                const uint32_t t = f.index(x, y, z);
                const TopCell& tc = g.top[t];
                if (tc.empty()) continue;
                const uint32_t cell[3] = {x, y, z};
                const GridFrame sub = g.sub_frame(cell, tc);
                uint32_t refs = 0;
                for (uint32_t k = 0; k < sub.cells(); ++k) refs += g.leaves.count(tc.first_leaf + k);
                if (refs == 0) continue;
                visit(drawn_box(t, 0, f.cell_box(x, y, z), false, refs));
                for (uint32_t sz = 0; sz < sub.res[2]; ++sz)
                    for (uint32_t sy = 0; sy < sub.res[1]; ++sy)
                        for (uint32_t sx = 0; sx < sub.res[0]; ++sx) {
                            const uint32_t l = tc.first_leaf + sub.index(sx, sy, sz), n = g.leaves.count(l);
                            if (n) visit(drawn_box(l, 1, sub.cell_box(sx, sy, sz), true, n));
                        }
            }
}

DrawingLegend draw_legend(const Grid2Data&) {
    return {"cells", "0: the top grid's non-empty cells; 1: the non-empty cells of their sub-grids"};
}

}  // namespace thicket
