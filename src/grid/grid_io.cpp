// Grid payloads: the resolution (three uint32), then the cell offsets and the cell entries, each
// preceded by its length (uint64); a two-level grid's has the top resolution, the top cells, then
// the sub-grids' cell offsets and entries. Reading checks the lengths against the resolution and
// the bytes left before allocating (PayloadReader), then the structure; the proof over the
// primitives is adopt_grid's and adopt_grid2's (grid_io.h).
#include "thicket/grid/grid_io.h"

#include <istream>
#include <ostream>

#include "thicket/util/binary_io.h"

namespace thicket {

namespace {

void write_resolution(std::ostream& out, const GridFrame& frame) {
    for (const uint32_t n : frame.res) write_value(out, n);
}

/// Writes what read_cell_lists reads: the offsets, then the entries, each after its length.
void write_cell_lists(std::ostream& out, const CellLists& lists) {
    write_counted_array<uint64_t>(out, lists.start);
    write_counted_array<uint64_t>(out, lists.refs);
}

GridResolution read_resolution(PayloadReader& reader, const char* who) {
    GridResolution r;
    for (uint32_t& n : r.n) reader.value(n, "resolution");
    if (r.n[0] == 0 || r.n[1] == 0 || r.n[2] == 0 || r.cells() > kMaxGridCells)
        throw Error(std::string("invalid ") + who + ": resolution " + r.str() + " (at least 1 per axis, at most " +
                    std::to_string(kMaxGridCells) + " cells)");
    return r;
}

/// Reads the lists of `cells` cells; an empty scene has no lists at all.
void read_cell_lists(PayloadReader& reader, CellLists& lists, uint64_t cells, size_t primitive_count,
                     const char* who) {
    const uint64_t offsets = primitive_count ? cells + 1 : 0;
    reader.counted_array<uint64_t>(lists.start, offsets, "cell offsets");
    reader.counted_array<uint64_t>(lists.refs, primitive_count ? kMaxGridReferences : 0, "cell entries");
    if (primitive_count) check_cell_lists(lists, cells, primitive_count, who);
}

}  // namespace

void write_grid(std::ostream& out, const GridData& g) {
    write_resolution(out, g.frame);
    write_cell_lists(out, g.lists);
}

SavedGrid read_grid(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "grid");
    SavedGrid g;
    g.res = read_resolution(reader, "grid");
    read_cell_lists(reader, g.lists, g.res.cells(), primitive_count, "grid");
    reader.end();
    return g;
}

void write_grid2(std::ostream& out, const Grid2Data& g) {
    write_resolution(out, g.frame);
    write_counted_array<uint64_t>(out, g.top);
    write_cell_lists(out, g.leaves);
}

SavedGrid2 read_grid2(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "grid2");
    SavedGrid2 g;
    g.res = read_resolution(reader, "grid2");
    reader.counted_array<uint64_t>(g.top, primitive_count ? g.res.cells() : 0, "top cells");
    if (primitive_count && g.top.size() != g.res.cells())
        throw Error("invalid grid2: " + std::to_string(g.top.size()) + " top cells for a resolution of " +
                    g.res.str());
    // Sub-grids lie in the leaf lists in top cell order, each after the one before.
    uint64_t leaf_cells = 0;
    for (size_t c = 0; c < g.top.size(); ++c) {
        const TopCell& tc = g.top[c];
        const bool empty = tc.res[0] == 0 && tc.res[1] == 0 && tc.res[2] == 0 && tc.first_leaf == 0;
        const bool next = tc.res[0] != 0 && tc.res[1] != 0 && tc.res[2] != 0 && tc.first_leaf == leaf_cells;
        if (tc.unused != 0 || !(empty || next))
            throw Error("invalid grid2: top cell " + std::to_string(c) + " is neither empty nor the next sub-grid");
        leaf_cells += uint64_t(tc.res[0]) * tc.res[1] * tc.res[2];
        if (leaf_cells > kMaxGridCells)
            throw Error("invalid grid2: the sub-grids have more than " + std::to_string(kMaxGridCells) + " cells");
    }
    read_cell_lists(reader, g.leaves, leaf_cells, primitive_count, "grid2");
    reader.end();
    return g;
}

void check_cell_lists(const CellLists& lists, size_t cells, size_t primitive_count, const char* who) {
    const std::string invalid = std::string("invalid ") + who + ": ";
    if (lists.start.size() != cells + 1)
        throw Error(invalid + std::to_string(lists.start.size()) + " cell offsets for " + std::to_string(cells) +
                    " cells");
    if (lists.start.front() != 0 || lists.start.back() != lists.refs.size())
        throw Error(invalid + "the cell offsets do not span the " + std::to_string(lists.refs.size()) + " entries");
    // Every offset in order before any entry is read: only then do the first and last offsets
    // bound every cell's range (a later decrease once let an earlier cell read past the entries).
    for (size_t c = 0; c < cells; ++c)
        if (lists.start[c] > lists.start[c + 1])
            throw Error(invalid + "the offsets of cell " + std::to_string(c) + " are out of order");
    for (size_t c = 0; c < cells; ++c) {
        for (uint32_t k = lists.start[c]; k < lists.start[c + 1]; ++k) {
            const uint32_t id = lists.refs[k] & kPrimMask;
            if (id >= primitive_count)
                throw Error(invalid + "cell " + std::to_string(c) + " lists primitive " + std::to_string(id) + " of " +
                            std::to_string(primitive_count));
            if (k > lists.start[c] && id <= (lists.refs[k - 1] & kPrimMask))
                throw Error(invalid + "cell " + std::to_string(c) + " lists its primitives out of order or twice");
        }
    }
    std::vector<uint32_t> marked(lists.refs);
    for (uint32_t& r : marked) r &= kPrimMask;
    mark_single_cell_references(marked, primitive_count);
    if (marked != lists.refs) throw Error(invalid + "the single-cell marks are not those of its entries");
}

}  // namespace thicket
