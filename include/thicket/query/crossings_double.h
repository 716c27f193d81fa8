#pragma once
/// Every surface crossing of a double-precision ray, for `thicket trace --count/--all` and the
/// module's count_intersections/list_intersections on float64 rays: the precision=double
/// structures answer closest hits in double (Accel::intersect_double) and nothing else, so the
/// crossings are found as Accel::all_hits finds them for float rays by default, asking the
/// closest hit again from just past each crossing, every step in double.
#include <cmath>
#include <cstdint>
#include <algorithm>
#include <limits>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/core/ray_double.h"

namespace thicket {

/// The smallest t after `t` that starts a new crossing: next_crossing_t's rule (kSameCrossing
/// relative, so that a ray through a shared edge or vertex crosses once) with double's spacing.
inline double next_crossing_t_double(double t) {
    return std::nextafter(t + double(kSameCrossing) * std::fabs(t), std::numeric_limits<double>::infinity());
}

/// Appends the crossings of `ray` within [ray.tmin, ray.tmax], sorted by t, to `out`. The
/// structure must be double_precision() (intersect_double throws Error naming precision=double
/// otherwise) and the ray meaningful (make_ray()).
inline void all_hits_double(const Accel& accel, const RayD& ray, std::vector<HitD>& out) {
    RayD rest = ray;
    for (;;) {
        const HitD hit = accel.intersect_double(rest);
        if (!hit.found()) return;
        out.push_back(hit);
        // The interval must shrink, or a hit answered before tmin would loop forever; a t that
        // cannot grow (inf) ends the ray.
        const double next = next_crossing_t_double(hit.t);
        if (!(next > rest.tmin) || !(next <= rest.tmax) || !std::isfinite(next)) return;
        rest.tmin = next;
    }
}

/// The number of crossings all_hits_double() lists.
inline uint32_t count_hits_double(const Accel& accel, const RayD& ray) {
    std::vector<HitD> hits;
    all_hits_double(accel, ray, hits);
    return uint32_t(hits.size());
}

/// Every crossing of each ray, HitLists' layout: rays[i]'s are hits[splits[i] .. splits[i+1]).
struct HitListsD {
    std::vector<size_t> splits;
    std::vector<HitD> hits;
};

}  // namespace thicket
