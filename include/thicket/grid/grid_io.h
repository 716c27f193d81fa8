#pragma once
/// Saved grids (uniform and two-level): payload I/O and the load-time proof. Reading checks the
/// cell lists' structure (offsets in order and spanning the entries, primitive ids in range and
/// ascending in each cell, the single-cell marks exactly those the build sets). Adopting them
/// over the primitives pins the frames to the ones the spec's options give for the scene (for a
/// two-level grid, every sub-grid's too) and replays the builder's assignment (cells_of, the
/// same code on the same frames): every cell the builder would give a primitive must list it, so
/// a grid that would miss a primitive is refused. Extra entries only cost time (a primitive
/// tested where it cannot be hit). The proof costs about what assigning the primitives to cells
/// costs in a build.
#include <algorithm>
#include <iosfwd>
#include <span>
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/grid/assign.h"
#include "thicket/grid/cells.h"
#include "thicket/grid/grid2_build.h"
#include "thicket/grid/grid_build.h"

namespace thicket {

/// A uniform grid as read from a payload, structure checked, not yet proved over primitives.
struct SavedGrid {
    GridResolution res;
    CellLists lists;  ///< empty for an empty scene
};

/// A two-level grid as read from a payload: top cells in order (each empty, or the next sub-grid
/// in the leaf lists), lists structure checked; not yet proved over primitives.
struct SavedGrid2 {
    GridResolution res;         ///< the top level's
    std::vector<TopCell> top;   ///< empty for an empty scene
    CellLists leaves;
};

/// Payload I/O for save_accel/load_accel.
void write_grid(std::ostream& out, const GridData& g);
SavedGrid read_grid(std::istream& in, size_t primitive_count);
void write_grid2(std::ostream& out, const Grid2Data& g);
SavedGrid2 read_grid2(std::istream& in, size_t primitive_count);

/// Throws Error ("invalid <who>: ...") unless `lists` has `cells` cells whose offsets are in
/// order and span the entries, whose entries are primitive ids below `primitive_count`, strictly
/// ascending in each cell, marked kSingleCell exactly where the build marks them.
void check_cell_lists(const CellLists& lists, size_t cells, size_t primitive_count, const char* who);

namespace grid_detail {

/// Throws Error unless each primitive of `ids` is listed by every cell of frame `f` that the
/// builder assigns it to; cell c of `f` is cell first + c of `lists` (checked by check_cell_lists).
template <PrimitiveSet P>
void prove_cells(const P& prims, std::span<const uint32_t> ids, const GridFrame& f, GridAssign mode,
                 const CellLists& lists, size_t first, const char* who) {
    const auto by_id = [](uint32_t a, uint32_t b) { return (a & kPrimMask) < (b & kPrimMask); };
    std::vector<uint32_t> cells;
    for (const uint32_t id : ids) {
        cells.clear();
        cells_of(prims, id, f, mode, cells);
        for (const uint32_t c : cells) {
            const uint32_t* begin = lists.refs.data() + lists.start[first + c];
            const uint32_t* end = lists.refs.data() + lists.start[first + c + 1];
            if (!std::binary_search(begin, end, id, by_id))
                throw Error(std::string("invalid ") + who + ": cell " + std::to_string(first + c) +
                            " does not list primitive " + std::to_string(id) + ", which overlaps it");
        }
    }
}

/// The frame over `box` at `res`, the resolution the spec's options give for this scene; throws
/// Error ("invalid <who>: <what> ...") when the saved resolution is another.
inline GridFrame proved_frame(const Aabb& box, const GridResolution& res, const GridResolution& saved,
                              const char* who, const char* what) {
    if (res.n != saved.n)
        throw Error(std::string("invalid ") + who + ": " + what + " " + saved.str() +
                    ", where the spec's options give " + res.str() + " for this scene");
    return GridFrame::make(box, res);
}

}  // namespace grid_detail

/// The grid `saved` over `prims`, proved to answer like the grid build_grid(prims, o) makes:
/// throws Error when its resolution is not the one `o` gives for this scene, or when a cell
/// misses a primitive the builder would put in it.
template <PrimitiveSet P>
GridData adopt_grid(const P& prims, SavedGrid saved, const GridOptions& o) {
    GridData g;
    g.box = grid_scene_bounds(prims, "grid");
    if (prims.size() == 0) return g;  // read_grid has checked that there are no cells
    g.frame =
        grid_detail::proved_frame(g.box, grid_resolution(g.box, prims.size(), o), saved.res, "grid", "resolution");
    grid_detail::prove_cells(prims, std::span<const uint32_t>(every_primitive(prims.size())), g.frame, o.assign,
                             saved.lists, 0, "grid");
    g.lists = std::move(saved.lists);
    return g;
}

/// The two-level grid `saved` over `prims`, proved to answer like the one build_grid2(prims, o)
/// makes: throws Error when its top resolution, or a top cell's sub-grid, is not the builder's,
/// or when a sub-grid cell misses a primitive the builder would put in it. The top level's cell
/// lists are not saved: they are rebuilt here, as the builder makes them.
template <PrimitiveSet P>
Grid2Data adopt_grid2(const P& prims, SavedGrid2 saved, const Grid2Options& o) {
    Grid2Data g;
    g.box = grid_scene_bounds(prims, "grid2");
    if (prims.size() == 0) return g;  // read_grid2 has checked that there are no cells
    g.frame = grid_detail::proved_frame(g.box, grid2_top_resolution(g.box, prims.size(), o), saved.res, "grid2",
                                        "top resolution");
    AssignScratch scratch;
    const CellLists top = assign_every_primitive(prims, g.frame, o.assign, scratch);
    g.frame.for_each_cell([&](const uint32_t cell[3], uint32_t c) {
        const uint32_t count = top.count(c);
        const TopCell& tc = saved.top[c];
        GridResolution want{{0, 0, 0}};
        if (count) want = grid2_sub_resolution(g.frame.cell_box(cell), count, o);
        const GridResolution got{{tc.res[0], tc.res[1], tc.res[2]}};
        if (got.n != want.n)
            throw Error("invalid grid2: top cell " + std::to_string(c) + " has a " + got.str() +
                        " sub-grid, where the builder makes " + want.str() + " for its " + std::to_string(count) +
                        " primitives");
        if (count == 0) return;
        const std::span<const uint32_t> members(top.refs.data() + top.start[c], count);
        grid_detail::prove_cells(prims, members, g.sub_frame(cell, tc), o.assign, saved.leaves, tc.first_leaf,
                                 "grid2");
    });
    g.top = std::move(saved.top);
    g.leaves = std::move(saved.leaves);
    g.top_references = top.refs.size();
    return g;
}

}  // namespace thicket
