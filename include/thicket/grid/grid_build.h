#pragma once
/// Building the uniform grid: resolution from the density rule (or an explicit count), then the
/// compact cell lists by counting, prefix sum and fill.
#include <numeric>
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/grid/assign.h"
#include "thicket/grid/cells.h"
#include "thicket/grid/frame.h"
#include "thicket/grid/resolution.h"

namespace thicket {

struct GridOptions {
    double lambda = 5.0;      ///< cells per primitive for the automatic resolution
    uint32_t res = 0;         ///< cells along the longest axis; 0: automatic (lambda)
    bool mailbox = true;      ///< per-ray mailbox: test each primitive once per ray
    GridAssign assign = GridAssign::Clip;
};

struct GridData {
    Aabb box;           ///< bounds of every primitive (empty for an empty scene)
    GridFrame frame;
    CellLists lists;    ///< empty for an empty scene
};

/// Bounds of all primitives; throws when there are too many for 31-bit ids.
template <PrimitiveSet P>
Aabb grid_scene_bounds(const P& prims, const char* who) {
    if (prims.size() > kPrimMask)
        throw Error(std::string(who) + ": " + std::to_string(prims.size()) + " primitives; at most " +
                    std::to_string(kPrimMask) + " are supported");
    Aabb box;
    for (uint32_t i = 0; i < prims.size(); ++i) box.grow(prims.bounds(i));
    return box;
}

/// The resolution of a grid over `prims` primitives whose bounds are `box`.
inline GridResolution grid_resolution(const Aabb& box, size_t prims, const GridOptions& o) {
    return o.res ? longest_axis_resolution(box.extent(), o.res, "grid: res=" + std::to_string(o.res))
                 : density_resolution(box.extent(), o.lambda * double(prims), uint32_t(kMaxGridCells), kMaxGridCells);
}

/// The ids 0 .. prims - 1: every primitive, in id order.
inline std::vector<uint32_t> every_primitive(size_t prims) {
    std::vector<uint32_t> ids(prims);
    std::iota(ids.begin(), ids.end(), 0u);
    return ids;
}

/// The cell lists of every primitive of `prims` over `frame`, as the grid builders assign them,
/// closed by the final offset: the uniform grid's lists and the two-level grid's top level.
template <PrimitiveSet P>
CellLists assign_every_primitive(const P& prims, const GridFrame& frame, GridAssign assign, AssignScratch& scratch) {
    CellLists lists;
    lists.start.reserve(size_t(frame.cells()) + 1);
    append_cell_lists(prims, std::span<const uint32_t>(every_primitive(prims.size())), frame, assign, lists, scratch);
    lists.start.push_back(uint32_t(lists.refs.size()));
    return lists;
}

template <PrimitiveSet P>
GridData build_grid(const P& prims, const GridOptions& o) {
    GridData g;
    g.box = grid_scene_bounds(prims, "grid");
    if (prims.size() == 0) return g;
    g.frame = GridFrame::make(g.box, grid_resolution(g.box, prims.size(), o));
    AssignScratch scratch;
    g.lists = assign_every_primitive(prims, g.frame, o.assign, scratch);
    mark_single_cell_references(g.lists.refs, prims.size());
    return g;
}

}  // namespace thicket
