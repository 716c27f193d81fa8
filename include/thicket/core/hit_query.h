#pragma once
/// The closest-hit and any-hit entry points every tree traversal shares. A structure's query
/// class Query<AnyHit, Prims, C> is made from (data, prims, ray, hit, counters); its run(args...)
/// searches [ray.tmin, hit.t], narrowing `hit` to the closest hit (AnyHit false), or returns
/// whether anything is hit, stopping at the first (AnyHit true).
#include <cstdint>
#include <vector>

#include "thicket/core/ray.h"
#include "thicket/core/traversal_record.h"

namespace thicket {

/// What every structure's Query holds and does alike (it derives from this): the structure's
/// data, its primitives, the ray, the hit it narrows and the counters; the end of the interval
/// still searched; and the leaf test. A structure that records its steps for the explorer
/// (kRecordsSteps) says so with Records: its primitive tests are then told to a recording counter.
/// S is the scalar of the rays and hits (double for the `precision=double` BVH).
template <bool AnyHit, class Data, class Prims, class C, bool Records = false, class S = float>
struct QueryState {
    const Data& data;
    const Prims& prims;
    const RayT<S>& ray;
    HitT<S>& hit;
    C& counters;

    QueryState(const Data& d, const Prims& p, const RayT<S>& r, HitT<S>& h, C& c)
        : data(d), prims(p), ray(r), hit(h), counters(c) {}

    /// The far end of the interval still searched: tmax for any hit, the closest hit so far else.
    S far() const { return AnyHit ? ray.tmax : hit.t; }

    /// Tests primitives order[first .. end); true ends the query (any hit found one). With
    /// Records, a recording counter (RecordsSteps) hears of each test, the blocker's too.
    bool test_prims(const std::vector<uint32_t>& order, uint32_t first, uint32_t end) {
        return test_prims(order, first, end, [](uint32_t) { return true; });
    }
    /// Same, testing only the primitives for which `fresh(p)` is true (a mailbox's first_visit(),
    /// for structures that reference a primitive from several cells).
    template <class Fresh>
    bool test_prims(const std::vector<uint32_t>& order, uint32_t first, uint32_t end, Fresh&& fresh) {
        for (uint32_t i = first; i < end; ++i) {
            const uint32_t p = order[i];
            if (!fresh(p)) continue;
            counters.prim();
            if constexpr (AnyHit) {
                if (prims.occludes(p, ray)) {
                    if constexpr (Records && RecordsSteps<C>) counters.record_prim(p, far());
                    return true;
                }
            } else {
                prims.intersect(p, ray, hit);
            }
            if constexpr (Records && RecordsSteps<C>) counters.record_prim(p, far());
        }
        return false;
    }
};

/// Closest hit within [ray.tmin, ray.tmax] (prim == kNoPrim on a miss).
template <template <bool, class, class> class Query, class Data, class Prims, class C, class... Args>
Hit closest_hit(const Data& data, const Prims& prims, const Ray& ray, C& counters, Args... args) {
    Hit hit = miss_for(ray);
    Query<false, Prims, C>(data, prims, ray, hit, counters).run(args...);
    return hit;
}

/// Whether anything is hit within [ray.tmin, ray.tmax]; stops at the first hit.
template <template <bool, class, class> class Query, class Data, class Prims, class C, class... Args>
bool any_hit(const Data& data, const Prims& prims, const Ray& ray, C& counters, Args... args) {
    Hit unused = miss_for(ray);
    return Query<true, Prims, C>(data, prims, ray, unused, counters).run(args...);
}

}  // namespace thicket
