#pragma once
/// Ray/triangle intersection: Moller-Trumbore (1997) and the watertight test of Woop, Benthin
/// & Wald (2013). Both report barycentrics u (weight of v1) and v (weight of v2) and accept a hit
/// only with tmin <= t <= tmax.
#include <cmath>
#include <utility>

#include "thicket/core/ray.h"

namespace thicket {

enum class TriangleTest { Moller, Watertight };

struct TriangleHit {
    float t, u, v;
};

/// Moller-Trumbore. No epsilon on the determinant: only an exactly parallel or degenerate
/// triangle is rejected, so thin triangles are still hit; NaN results fail every comparison.
inline bool intersect_moller(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Ray& ray, float tmax,
                             TriangleHit& out) {
    const Vec3 e1 = v1 - v0, e2 = v2 - v0;
    const Vec3 p = cross(ray.dir, e2);
    const float det = dot(e1, p);
    if (det == 0.0f) return false;
    const float inv_det = 1.0f / det;
    const Vec3 s = ray.org - v0;
    const float u = dot(s, p) * inv_det;
    if (!(u >= 0.0f && u <= 1.0f)) return false;
    const Vec3 q = cross(s, e1);
    const float v = dot(ray.dir, q) * inv_det;
    if (!(v >= 0.0f && u + v <= 1.0f)) return false;
    const float t = dot(e2, q) * inv_det;
    if (!(t >= ray.tmin && t <= tmax)) return false;
    out = {t, u, v};
    return true;
}

/// Watertight test: no ray passes between two triangles that share an edge, because the edge
/// functions are evaluated in a ray-aligned shear space and recomputed in double on exact zeros.
inline bool intersect_watertight(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Ray& ray, float tmax,
                                 TriangleHit& out) {
    const Vec3 ad = abs(ray.dir);
    const int kz = max_axis(ad);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (ray.dir[kz] < 0.0f) std::swap(kx, ky);  // keep the winding of the shear space
    const float sx = ray.dir[kx] / ray.dir[kz];
    const float sy = ray.dir[ky] / ray.dir[kz];
    const float sz = 1.0f / ray.dir[kz];

    const Vec3 a = v0 - ray.org, b = v1 - ray.org, c = v2 - ray.org;
    const float ax = a[kx] - sx * a[kz], ay = a[ky] - sy * a[kz];
    const float bx = b[kx] - sx * b[kz], by = b[ky] - sy * b[kz];
    const float cx = c[kx] - sx * c[kz], cy = c[ky] - sy * c[kz];

    float U = cx * by - cy * bx;
    float V = ax * cy - ay * cx;
    float W = bx * ay - by * ax;
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        U = float(double(cx) * double(by) - double(cy) * double(bx));
        V = float(double(ax) * double(cy) - double(ay) * double(cx));
        W = float(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
    const float det = U + V + W;
    if (det == 0.0f || std::isnan(det)) return false;

    const float T = U * (sz * a[kz]) + V * (sz * b[kz]) + W * (sz * c[kz]);
    const float inv_det = 1.0f / det;
    const float t = T * inv_det;
    if (!(t >= ray.tmin && t <= tmax)) return false;
    out = {t, V * inv_det, W * inv_det};
    return true;
}

template <TriangleTest Test>
inline bool intersect_triangle(const Vec3& v0, const Vec3& v1, const Vec3& v2, const Ray& ray, float tmax,
                               TriangleHit& out) {
    if constexpr (Test == TriangleTest::Moller)
        return intersect_moller(v0, v1, v2, ray, tmax, out);
    else
        return intersect_watertight(v0, v1, v2, ray, tmax, out);
}

}  // namespace thicket
