#pragma once
/// Two-level grid traversal: a DDA over the top level; in each non-empty top cell a second DDA
/// over its sub-grid, started where the ray enters that top cell. The hit-inside-cell rule holds
/// at both levels: once the nearest hit lies within the current leaf cell's exit distance, the
/// leaf walk ends, and with it the top walk.
#include <algorithm>

#include "thicket/core/ray_box.h"
#include "thicket/grid/dda.h"
#include "thicket/grid/grid2_build.h"
#include "thicket/grid/visit.h"

namespace thicket {

/// Closest hit (AnyHit = false: updates `hit`) or any hit (AnyHit = true: returns whether the
/// ray is blocked within [tmin, tmax]); `mailboxing` turns the per-ray mailbox on, shared by all sub-grids
/// (a primitive may be referenced from several top cells).
template <bool AnyHit, PrimitiveSet Prims, class C>
bool grid2_walk(const Grid2Data& g, const Prims& prims, const Ray& ray, Hit& hit, bool mailboxing, C& counters) {
    if (g.leaves.refs.empty()) return false;
    const float t0 = ray_box_entry(RayBoxQuery(ray), g.frame.min, g.frame.max, ray.tmin, ray.tmax);
    if (t0 == kInfinity) return false;
    const DdaRay r(ray);
    RayMailbox mailbox(mailboxing);
    const uint32_t* start = g.leaves.start.data();
    const uint32_t* refs = g.leaves.refs.data();
    const auto far = [&] { return AnyHit ? ray.tmax : hit.t; };
    float t_enter = t0;
    return walk_cells(g.frame, r, t0, far, [&](const Dda& top) {
        counters.node();
        const TopCell& tc = g.top[top.index];
        if (!tc.empty()) {
            const GridFrame sub = g.sub_frame(top.cell, tc);
            const bool ended = walk_cells(sub, r, t_enter, far, [&](const Dda& leaf) {
                counters.node();
                const uint32_t l = tc.first_leaf + leaf.index;
                return grid_detail::visit_cell<AnyHit>(refs + start[l], refs + start[l + 1], prims, ray, hit, mailbox,
                                                       counters);
            });
            if (ended) return true;
        }
        // The leaf walk ended by leaving the sub-grid, or because the nearest hit lies within its
        // current cell, hence within this top cell: then the top step stops too (were rounding to
        // put the hit a hair beyond this cell's exit, one more cell would be walked, harmlessly).
        // The next top cell's walk starts where this one ends.
        t_enter = std::max(t0, std::min({top.next[0], top.next[1], top.next[2]}));
        return false;
    });
}

}  // namespace thicket
