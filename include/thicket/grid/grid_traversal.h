#pragma once
/// Uniform grid traversal: the slab test finds where the ray enters the grid's box, the DDA walks
/// the cells from there. A hit found in a cell may lie beyond that cell (its primitive reaches
/// into later cells); it is kept, and the walk stops only once the nearest hit lies within the
/// current cell's exit distance, as nothing in later cells can be nearer.
#include <algorithm>

#include "thicket/core/ray_box.h"
#include "thicket/core/traversal_record.h"
#include "thicket/grid/dda.h"
#include "thicket/grid/grid_build.h"
#include "thicket/grid/visit.h"

namespace thicket {

/// Where the ray enters the walk's current cell: the last of the cell's entry planes it crosses,
/// not before t0 (where it entered the grid). Only recording asks (the walk itself needs exits).
inline float dda_cell_entry(const Dda& d, const DdaRay& r, float t0) {
    float t = t0;
    for (int a = 0; a < 3; ++a)
        if (r.step[a] != 0) t = std::max(t, d.base[a] + float(d.cell[a] + 1 - r.up[a]) * d.delta[a]);
    return t;
}

/// Closest hit (AnyHit = false: updates `hit`) or any hit (AnyHit = true: returns whether the
/// ray is blocked within [tmin, tmax]); `mailboxing` turns the per-ray mailbox on.
template <bool AnyHit, PrimitiveSet Prims, class C>
bool grid_walk(const GridData& g, const Prims& prims, const Ray& ray, Hit& hit, bool mailboxing, C& counters) {
    if (g.lists.refs.empty()) return false;
    const float t0 = ray_box_entry(RayBoxQuery(ray), g.frame.min, g.frame.max, ray.tmin, ray.tmax);
    if (t0 == kInfinity) return false;
    const DdaRay r(ray);
    RayMailbox mailbox(mailboxing);
    const uint32_t* start = g.lists.start.data();
    const uint32_t* refs = g.lists.refs.data();
    // Stop when the nearest hit (or the end of the ray) lies within this cell: not past its exit.
    return walk_cells(g.frame, r, t0, [&] { return AnyHit ? ray.tmax : hit.t; }, [&](const Dda& dda) {
        counters.node();
        if constexpr (RecordsSteps<C>) counters.record_node(dda.index, dda_cell_entry(dda, r, t0));
        return grid_detail::visit_cell<AnyHit>(refs + start[dda.index], refs + start[dda.index + 1], prims, ray, hit,
                                               mailbox, counters);
    });
}

}  // namespace thicket
