#pragma once
/// What double precision adds to the rays, hits, boxes and triangle tests that core/ray.h,
/// aabb.h and triangle.h write once for both scalars: conversions between the precisions and
/// the double slab test. The `precision=double` structures (brute, bvh) compute with them, for
/// coordinates far from the origin (georeferenced lidar at 1e6 m, planetary scenes at 1e7 m)
/// where float's 24-bit mantissa leaves centimetres to metres between representable points.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"
#include "thicket/core/triangle.h"

namespace thicket {

/// A float ray widened exactly to double.
inline RayD to_double(const Ray& r) {
    const double inf = std::numeric_limits<double>::infinity();
    return {Vec3d(r.org), r.tmin == kInfinity ? inf : double(r.tmin), Vec3d(r.dir),
            r.tmax == kInfinity ? inf : double(r.tmax)};
}
/// The double hit rounded to float (t beyond float's range becomes +inf).
inline Hit to_hit(const HitD& h) { return {float(h.t), float(h.u), float(h.v), h.prim}; }
/// The smallest float box holding `b` (rounded outward): what a float builder may split on
/// without a primitive ever leaving its node's double box.
inline Aabb outward_float_box(const AabbD& b) {
    if (b.empty()) return Aabb{};
    Aabb f;
    for (int a = 0; a < 3; ++a) {
        float lo = float(b.min[a]), hi = float(b.max[a]);
        if (double(lo) > b.min[a]) lo = std::nextafter(lo, -kInfinity);
        if (double(hi) < b.max[a]) hi = std::nextafter(hi, kInfinity);
        f.min[a] = lo;
        f.max[a] = hi;
    }
    return f;
}

/// Per-ray data of the double slab test (as RayBoxQuery, core/ray_box.h).
struct RayBoxQueryD {
    Vec3d org;
    Vec3d inv_dir;
    int neg[3];
    explicit RayBoxQueryD(const RayD& r) : org(r.org), inv_dir(1.0 / r.dir.x, 1.0 / r.dir.y, 1.0 / r.dir.z) {
        for (int a = 0; a < 3; ++a) neg[a] = std::signbit(inv_dir[a]) ? 1 : 0;
    }
};

/// Relative slack on both ends of every double slab interval, for the same reason as kSlabSlack
/// (the triangle test's own t may be off by more than the slab's rounding), scaled to double:
/// far below anything float could resolve, far above double's rounding of the tests.
inline constexpr double kSlabSlackD = 1e-12;

/// Distance at which the ray enters the box [lo, hi] within [tmin, tmax], or +inf if it misses;
/// robust in the same ways as ray_box_entry() (Ize's bound for double, NaN axes dropped).
inline double ray_box_entry(const RayBoxQueryD& q, const Vec3d& lo, const Vec3d& hi, double tmin, double tmax) {
    constexpr double eps = 0.5 * std::numeric_limits<double>::epsilon();
    constexpr double gamma3 = 3 * eps / (1 - 3 * eps);
    constexpr double grow = 1.0 + 2.0 * gamma3 + kSlabSlackD;
    constexpr double shrink = 1.0 - 2.0 * gamma3 - kSlabSlackD;
    const Vec3d* planes[2] = {&lo, &hi};
    double t0 = tmin, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        double near_t = ((*planes[q.neg[a]])[a] - q.org[a]) * q.inv_dir[a];
        double far_t = ((*planes[1 - q.neg[a]])[a] - q.org[a]) * q.inv_dir[a];
        near_t *= near_t > 0.0 ? (1.0 - kSlabSlackD) : (1.0 + kSlabSlackD);
        far_t *= far_t > 0.0 ? grow : shrink;
        t0 = near_t > t0 ? near_t : t0;  // a NaN candidate is dropped, as in ray_box_entry()
        t1 = far_t < t1 ? far_t : t1;
    }
    return t0 <= t1 ? t0 : std::numeric_limits<double>::infinity();
}

/// Whether t lies in the ray's interval through `bounds` (hit_within_bounds() in double).
inline bool hit_within_bounds(const RayD& ray, double t, const AabbD& bounds) {
    return ray_box_entry(RayBoxQueryD(ray), bounds.min, bounds.max, t, t) != std::numeric_limits<double>::infinity();
}

}  // namespace thicket
