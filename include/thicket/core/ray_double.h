#pragma once
/// Double-precision vectors, rays, hits, boxes and the ray/box and ray/triangle tests in double:
/// what the `precision=double` structures (brute, bvh) compute with, for coordinates far from
/// the origin (georeferenced lidar at 1e6 m, planetary scenes at 1e7 m) where float's 24-bit
/// mantissa leaves centimetres to metres between representable points.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "thicket/core/ray.h"
#include "thicket/core/triangle.h"
#include "thicket/core/vec3d.h"

namespace thicket {

/// A double-precision ray: accepts hits with tmin <= t <= tmax, t in units of dir's length.
struct RayD {
    Vec3d org;
    double tmin = 0.0;
    Vec3d dir;
    double tmax = std::numeric_limits<double>::infinity();
};

/// A double-precision closest hit; prim == kNoPrim means no hit. (u, v) as in Hit.
struct HitD {
    double t = std::numeric_limits<double>::infinity();
    double u = 0.0;
    double v = 0.0;
    uint32_t prim = kNoPrim;

    constexpr bool found() const { return prim != kNoPrim; }
};

/// The double ray of 8 doubles (origin, direction, tmin, tmax); false, `ray` untouched, for a
/// ray without meaning, by the same rules as make_ray().
inline bool make_ray_double(const double* r, RayD& ray) {
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(r[i])) return false;
    if (std::isnan(r[6]) || std::isnan(r[7]) || r[6] > r[7]) return false;
    if (r[3] == 0.0 && r[4] == 0.0 && r[5] == 0.0) return false;
    ray.org = {r[0], r[1], r[2]};
    ray.dir = {r[3], r[4], r[5]};
    ray.tmin = r[6];
    ray.tmax = r[7];
    return true;
}

/// A float ray widened exactly to double.
inline RayD to_double(const Ray& r) {
    const double inf = std::numeric_limits<double>::infinity();
    return {Vec3d(r.org), r.tmin == kInfinity ? inf : double(r.tmin), Vec3d(r.dir),
            r.tmax == kInfinity ? inf : double(r.tmax)};
}
/// The double hit rounded to float (t beyond float's range becomes +inf).
inline Hit to_hit(const HitD& h) { return {float(h.t), float(h.u), float(h.v), h.prim}; }
/// Starts a closest-hit query: the search interval's far end is the ray's tmax.
constexpr HitD miss_for(const RayD& ray) { return HitD{ray.tmax, 0.0, 0.0, kNoPrim}; }

struct AabbD {
    Vec3d min{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
              std::numeric_limits<double>::infinity()};
    Vec3d max{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
              -std::numeric_limits<double>::infinity()};
    constexpr void grow(Vec3d p) { min = thicket::min(min, p); max = thicket::max(max, p); }
    constexpr void grow(const AabbD& b) { min = thicket::min(min, b.min); max = thicket::max(max, b.max); }
    constexpr bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
};

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

struct TriangleHitD {
    double t, u, v;
};

/// Moller-Trumbore in double; the same acceptance rules as intersect_moller().
inline bool intersect_moller(const Vec3d& v0, const Vec3d& v1, const Vec3d& v2, const RayD& ray, double tmax,
                             TriangleHitD& out) {
    const Vec3d e1 = v1 - v0, e2 = v2 - v0;
    const Vec3d p = cross(ray.dir, e2);
    const double det = dot(e1, p);
    if (det == 0.0) return false;
    const double inv_det = 1.0 / det;
    const Vec3d s = ray.org - v0;
    const double u = dot(s, p) * inv_det;
    if (!(u >= 0.0 && u <= 1.0)) return false;
    const Vec3d q = cross(s, e1);
    const double v = dot(ray.dir, q) * inv_det;
    if (!(v >= 0.0 && u + v <= 1.0)) return false;
    const double t = dot(e2, q) * inv_det;
    if (!(t >= ray.tmin && t <= tmax)) return false;
    out = {t, u, v};
    return true;
}

/// The watertight test (Woop, Benthin & Wald 2013) in double, as intersect_watertight(); exact
/// zeros of the edge functions are not recomputed (there is no wider type at hand): a ray
/// through a shared edge then hits both triangles or neither side's test fails alone.
inline bool intersect_watertight(const Vec3d& v0, const Vec3d& v1, const Vec3d& v2, const RayD& ray, double tmax,
                                 TriangleHitD& out) {
    const Vec3d ad{std::fabs(ray.dir.x), std::fabs(ray.dir.y), std::fabs(ray.dir.z)};
    const int kz = (ad.x >= ad.y && ad.x >= ad.z) ? 0 : (ad.y >= ad.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (ray.dir[kz] < 0.0) std::swap(kx, ky);
    const double sx = ray.dir[kx] / ray.dir[kz], sy = ray.dir[ky] / ray.dir[kz], sz = 1.0 / ray.dir[kz];
    const Vec3d a = v0 - ray.org, b = v1 - ray.org, c = v2 - ray.org;
    const double ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    const double bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    const double cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];
    const double U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
    if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return false;
    const double det = U + V + W;
    if (det == 0.0 || std::isnan(det)) return false;
    const double T = U * (sz * a[kz]) + V * (sz * b[kz]) + W * (sz * c[kz]);
    const double inv_det = 1.0 / det;
    const double t = T * inv_det;
    if (!(t >= ray.tmin && t <= tmax)) return false;
    out = {t, V * inv_det, W * inv_det};
    return true;
}

template <TriangleTest Test>
inline bool intersect_triangle(const Vec3d& v0, const Vec3d& v1, const Vec3d& v2, const RayD& ray, double tmax,
                               TriangleHitD& out) {
    if constexpr (Test == TriangleTest::Moller)
        return intersect_moller(v0, v1, v2, ray, tmax, out);
    else
        return intersect_watertight(v0, v1, v2, ray, tmax, out);
}

}  // namespace thicket
