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
#include "thicket/core/ray_box.h"

namespace thicket {

/// Appends the crossings of `ray` within [ray.tmin, ray.tmax], sorted by t, to `out`
/// (step_crossings over Accel::intersect_double). The structure must be double_precision()
/// (intersect_double throws Error naming precision=double otherwise) and the ray meaningful
/// (make_ray()).
inline void all_hits_double(const Accel& accel, const RayD& ray, std::vector<HitD>& out) {
    step_crossings(ray, [&](const RayD& rest) { return accel.intersect_double(rest); }, out);
}

/// The number of crossings all_hits_double() lists.
inline uint32_t count_hits_double(const Accel& accel, const RayD& ray) {
    std::vector<HitD> hits;
    all_hits_double(accel, ray, hits);
    return uint32_t(hits.size());
}

}  // namespace thicket
