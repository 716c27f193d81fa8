#pragma once
/// The closest-hit and any-hit entry points every tree traversal shares. A structure's query
/// class Query<AnyHit, Prims, C> is made from (data, prims, ray, hit, counters); its run(args...)
/// searches [ray.tmin, hit.t], narrowing `hit` to the closest hit (AnyHit false), or returns
/// whether anything is hit, stopping at the first (AnyHit true).
#include "thicket/core/ray.h"

namespace thicket {

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
