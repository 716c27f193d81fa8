#pragma once
/// Testing the primitives of one cell, with or without the per-ray mailbox. Shared by the uniform
/// and the two-level grid.
#include <cstdint>

#include "thicket/core/mailbox.h"
#include "thicket/core/ray.h"
#include "thicket/core/traversal_record.h"
#include "thicket/grid/cells.h"

namespace thicket {

namespace grid_detail {

/// Tests the cell entries [first, last): closest-hit updates `hit`; any-hit returns true at the
/// first primitive hit within [tmin, tmax]. A primitive met before on this ray is skipped when
/// mailboxing (it cannot change the answer: it was tested with a window at least as wide).
template <bool AnyHit, class Prims, class C>
inline bool visit_cell(const uint32_t* first, const uint32_t* last, const Prims& prims, const Ray& ray, Hit& hit,
                       RayMailbox& mailbox, C& counters) {
    for (; first != last; ++first) {
        const uint32_t ref = *first, id = ref & kPrimMask;
        if (!(ref & kSingleCell) && !mailbox.first_visit(id)) continue;
        counters.prim();
        if constexpr (AnyHit) {
            if (prims.occludes(id, ray)) {
                if constexpr (RecordsSteps<C>) counters.record_prim(id, ray.tmax);  // the blocker is listed too
                return true;
            }
        } else {
            prims.intersect(id, ray, hit);
        }
        if constexpr (RecordsSteps<C>) counters.record_prim(id, AnyHit ? ray.tmax : hit.t);
    }
    return false;
}

}  // namespace grid_detail
}  // namespace thicket
