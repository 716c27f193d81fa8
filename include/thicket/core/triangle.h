#pragma once
/// Ray/triangle intersection: Moller-Trumbore (1997) and the watertight test of Woop, Benthin
/// & Wald (2013). Both report barycentrics u (weight of v1) and v (weight of v2) and accept a hit
/// only with tmin <= t <= tmax.
#include <cmath>
#include <type_traits>
#include <utility>

#include "thicket/core/ray.h"

namespace thicket {

enum class TriangleTest { Moller, Watertight };

template <class S>
struct TriangleHitT {
    S t, u, v;
};
using TriangleHit = TriangleHitT<float>;
using TriangleHitD = TriangleHitT<double>;

// The tests are declared inline: as templates without it, GCC stopped inlining
// intersect_moller<float> into the kd-tree's leaf loop (9% of its primary-ray speed).

/// Moller-Trumbore. No epsilon on the determinant: only an exactly parallel or degenerate
/// triangle is rejected, so thin triangles are still hit; NaN results fail every comparison.
template <class S>
inline bool intersect_moller(const Vec3T<S>& v0, const Vec3T<S>& v1, const Vec3T<S>& v2, const RayT<S>& ray,
                      std::type_identity_t<S> tmax, TriangleHitT<S>& out) {
    const Vec3T<S> e1 = v1 - v0, e2 = v2 - v0;
    const Vec3T<S> p = cross(ray.dir, e2);
    const S det = dot(e1, p);
    if (det == S(0)) return false;
    const S inv_det = S(1) / det;
    const Vec3T<S> s = ray.org - v0;
    const S u = dot(s, p) * inv_det;
    if (!(u >= S(0) && u <= S(1))) return false;
    const Vec3T<S> q = cross(s, e1);
    const S v = dot(ray.dir, q) * inv_det;
    if (!(v >= S(0) && u + v <= S(1))) return false;
    const S t = dot(e2, q) * inv_det;
    if (!(t >= ray.tmin && t <= tmax)) return false;
    out = {t, u, v};
    return true;
}

/// Watertight test: no ray passes between two triangles that share an edge, because the edge
/// functions are evaluated in a ray-aligned shear space and, in float, recomputed in double on
/// exact zeros. In double there is no wider type at hand: a ray through a shared edge then hits
/// both triangles or neither side's test fails alone.
template <class S>
inline bool intersect_watertight(const Vec3T<S>& v0, const Vec3T<S>& v1, const Vec3T<S>& v2, const RayT<S>& ray,
                          std::type_identity_t<S> tmax, TriangleHitT<S>& out) {
    const Vec3T<S> ad = abs(ray.dir);
    const int kz = max_axis(ad);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (ray.dir[kz] < S(0)) std::swap(kx, ky);  // keep the winding of the shear space
    const S sx = ray.dir[kx] / ray.dir[kz];
    const S sy = ray.dir[ky] / ray.dir[kz];
    const S sz = S(1) / ray.dir[kz];

    const Vec3T<S> a = v0 - ray.org, b = v1 - ray.org, c = v2 - ray.org;
    const S ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    const S bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    const S cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];

    S U = cx * by - cy * bx;
    S V = ax * cy - ay * cx;
    S W = bx * ay - by * ax;
    if constexpr (std::is_same_v<S, float>) {
        if (U == 0.0f || V == 0.0f || W == 0.0f) {
            U = float(double(cx) * double(by) - double(cy) * double(bx));
            V = float(double(ax) * double(cy) - double(ay) * double(cx));
            W = float(double(bx) * double(ay) - double(by) * double(ax));
        }
    }
    if ((U < S(0) || V < S(0) || W < S(0)) && (U > S(0) || V > S(0) || W > S(0))) return false;
    const S det = U + V + W;
    if (det == S(0) || std::isnan(det)) return false;

    const S T = U * (sz * a[kz]) + V * (sz * b[kz]) + W * (sz * c[kz]);
    const S inv_det = S(1) / det;
    const S t = T * inv_det;
    if (!(t >= ray.tmin && t <= tmax)) return false;
    out = {t, V * inv_det, W * inv_det};
    return true;
}

template <TriangleTest Test, class S>
inline bool intersect_triangle(const Vec3T<S>& v0, const Vec3T<S>& v1, const Vec3T<S>& v2, const RayT<S>& ray,
                        std::type_identity_t<S> tmax, TriangleHitT<S>& out) {
    if constexpr (Test == TriangleTest::Moller)
        return intersect_moller(v0, v1, v2, ray, tmax, out);
    else
        return intersect_watertight(v0, v1, v2, ray, tmax, out);
}

}  // namespace thicket
