#pragma once
/// Building the two-level grid (Kalojanov, Billeter & Slusallek 2011): a coarse top-level grid
/// by the density rule over all primitives, then in every non-empty top cell a sub-grid by the
/// same rule over that cell's primitives. All sub-grids' cells share one compact list array, so
/// a top cell only needs its sub-grid's resolution and the index of its first cell.
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/grid/assign.h"
#include "thicket/grid/cells.h"
#include "thicket/grid/frame.h"
#include "thicket/grid/grid_build.h"
#include "thicket/grid/resolution.h"

namespace thicket {

struct Grid2Options {
    double top_density = 0.25;        ///< top-level cells per primitive
    double leaf_density = 1.25;       ///< sub-grid cells per primitive of the top cell
    bool mailbox = true;
    GridAssign assign = GridAssign::Clip;
};

/// A top-level cell: empty when res[0] == 0; otherwise its sub-grid has res[0] x res[1] x res[2]
/// cells, whose lists are leaves.start[first_leaf ...].
struct TopCell {
    uint32_t first_leaf = 0;
    uint8_t res[3] = {0, 0, 0};
    uint8_t unused = 0;

    bool empty() const { return res[0] == 0; }
};
static_assert(sizeof(TopCell) == 8, "two top cells per 16 bytes");

/// Largest sub-grid resolution per axis (it is stored in a byte).
inline constexpr uint32_t kMaxSubGridRes = 255;

struct Grid2Data {
    Aabb box;
    GridFrame frame;              ///< the top level
    std::vector<TopCell> top;     ///< frame.cells() entries; empty for an empty scene
    CellLists leaves;             ///< every sub-grid's cells, sub-grid after sub-grid
    size_t top_references = 0;    ///< primitive references of the top level (build only)

    /// The frame of the sub-grid of top cell (x, y, z); the build and the traversal both use this,
    /// so they agree on every plane.
    GridFrame sub_frame(const uint32_t cell[3], const TopCell& tc) const {
        GridResolution r;
        r.n = {tc.res[0], tc.res[1], tc.res[2]};
        return GridFrame::make(frame.cell_box(cell[0], cell[1], cell[2]), r);
    }
};

/// The top level's resolution over `prims` primitives whose bounds are `box`.
inline GridResolution grid2_top_resolution(const Aabb& box, size_t prims, const Grid2Options& o) {
    return density_resolution(box.extent(), o.top_density * double(prims), uint32_t(kMaxGridCells), kMaxGridCells);
}

/// The resolution of the sub-grid of the top cell `cell` holding `count` primitives.
inline GridResolution grid2_sub_resolution(const Aabb& cell, uint32_t count, const Grid2Options& o) {
    return density_resolution(cell.extent(), o.leaf_density * count, kMaxSubGridRes, kMaxGridCells);
}

template <PrimitiveSet P>
Grid2Data build_grid2(const P& prims, const Grid2Options& o) {
    Grid2Data g;
    g.box = grid_scene_bounds(prims, "grid2");
    if (prims.size() == 0) return g;
    g.frame = GridFrame::make(g.box, grid2_top_resolution(g.box, prims.size(), o));

    // Top level: which primitives each top cell holds.
    AssignScratch scratch;
    const CellLists top = assign_every_primitive(prims, g.frame, o.assign, scratch);
    g.top_references = top.refs.size();

    // Leaf level: a sub-grid per non-empty top cell, over that cell's primitives.
    g.top.resize(g.frame.cells());
    uint64_t leaf_cells = 0;
    g.frame.for_each_cell([&](const uint32_t cell[3], uint32_t c) {
        const uint32_t count = top.count(c);
        if (count == 0) return;
        const GridResolution r = grid2_sub_resolution(g.frame.cell_box(cell), count, o);
        leaf_cells += r.cells();
        if (leaf_cells > kMaxGridCells)
            throw Error("grid2: the sub-grids need more than " + std::to_string(kMaxGridCells) +
                        " cells (2^26) in all; use a smaller leaf density");
        TopCell& tc = g.top[c];
        tc.first_leaf = uint32_t(g.leaves.start.size());
        for (int a = 0; a < 3; ++a) tc.res[a] = uint8_t(r.n[a]);
        const std::span<const uint32_t> members(top.refs.data() + top.start[c], count);
        append_cell_lists(prims, members, g.sub_frame(cell, tc), o.assign, g.leaves, scratch);
    });
    g.leaves.start.push_back(uint32_t(g.leaves.refs.size()));
    mark_single_cell_references(g.leaves.refs, prims.size());
    return g;
}

}  // namespace thicket
