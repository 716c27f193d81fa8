#pragma once
/// Closest points: on a triangle (with its barycentrics) and the distance from a point to a box,
/// the two pieces every closest-point query is made of.
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

namespace thicket {

/// The closest point of a surface to a query point: prim == kNoPrim when there is none (an empty
/// scene). (u, v) are the primitive's surface parameters there, for triangles the barycentric
/// weights of vertices 1 and 2, as in Hit.
struct NearestPoint {
    Vec3 point{0, 0, 0};
    float distance = kInfinity;
    float u = 0.0f;
    float v = 0.0f;
    uint32_t prim = kNoPrim;

    constexpr bool found() const { return prim != kNoPrim; }
};

/// A primitive set that can say its primitive i's closest point to p (Triangles can; the shape
/// kernels cannot yet, so structures over shapes refuse closest-point queries).
template <class P>
concept HasClosestPoint = requires(const P& prims, uint32_t i, Vec3 p) {
    { prims.closest_point(i, p) } -> std::same_as<NearestPoint>;
};

/// Squared distance from p to the box (0 inside it), in double: its square of a distance past
/// 1.8e19 would overflow float to +inf and make far boxes look equally (infinitely) far.
inline double distance2_to_box(const Vec3& p, const Aabb& b) {
    double d2 = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double d = std::max({double(b.min[a]) - double(p[a]), 0.0, double(p[a]) - double(b.max[a])});
        d2 += d * d;
    }
    return d2;
}

/// Closest point of triangle (a, b, c) to p, by the Voronoi region of p: a vertex, an edge or the
/// face (Ericson, Real-Time Collision Detection, 5.1.5). (u, v) are the barycentric weights of b
/// and c. A degenerate triangle still answers a point on its segments, so distances never break.
struct TrianglePoint {
    Vec3 point;
    float u, v;
};

namespace detail {
/// Double-precision vectors for the closest-point arithmetic: its region tests multiply four
/// coordinate differences, which overflows float (to inf, then NaN) once a triangle's size times
/// the point's distance passes 1.8e19 (a point at 1e20 from a unit triangle); in double every
/// finite float input stays finite.
struct DVec {
    double x, y, z;
};
inline DVec dvec(const Vec3& v) { return {double(v.x), double(v.y), double(v.z)}; }
inline DVec operator-(const DVec& a, const DVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline DVec operator+(const DVec& a, const DVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline DVec operator*(const DVec& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double ddot(const DVec& a, const DVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 to_float(const DVec& v) { return {float(v.x), float(v.y), float(v.z)}; }
inline DVec on_segment(const DVec& p, const DVec& a, const DVec& b, double& w) {
    const DVec ab = b - a;
    const double len2 = ddot(ab, ab);
    w = len2 > 0 ? std::clamp(ddot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return a + ab * w;
}
}  // namespace detail

/// Distance from p to q, computed in double so that it is finite (and exact to float's rounding)
/// for every pair of finite float points whose distance is below float's maximum.
inline float point_distance(const Vec3& p, const Vec3& q) {
    const detail::DVec d = detail::dvec(p) - detail::dvec(q);
    return float(std::sqrt(detail::ddot(d, d)));
}

/// Closest point of segment a + w (b - a), w in [0, 1], to p; `w` receives w.
inline Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b, float& w) {
    double dw = 0.0;
    const Vec3 q = detail::to_float(detail::on_segment(detail::dvec(p), detail::dvec(a), detail::dvec(b), dw));
    w = float(dw);
    return q;
}
inline TrianglePoint closest_point_on_triangle(const Vec3& pf, const Vec3& af, const Vec3& bf, const Vec3& cf) {
    using detail::ddot;
    using detail::to_float;
    const detail::DVec p = detail::dvec(pf), a = detail::dvec(af), b = detail::dvec(bf), c = detail::dvec(cf);
    const detail::DVec ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ddot(ab, ap), d2 = ddot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return {af, 0, 0};
    const detail::DVec bp = p - b;
    const double d3 = ddot(ab, bp), d4 = ddot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return {bf, 1, 0};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double w = d1 / (d1 - d3);
        return {to_float(a + ab * w), float(w), 0};
    }
    const detail::DVec cp = p - c;
    const double d5 = ddot(ab, cp), d6 = ddot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return {cf, 0, 1};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return {to_float(a + ac * w), 0, float(w)};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {to_float(b + (c - b) * w), float(1 - w), float(w)};
    }
    const double sum = va + vb + vc;
    if (!(sum > 0)) {
        // No interior (collinear corners; rounding can bring a needle here): its three segments.
        double wab, wac, wbc;
        const detail::DVec qab = detail::on_segment(p, a, b, wab), qac = detail::on_segment(p, a, c, wac),
                           qbc = detail::on_segment(p, b, c, wbc);
        const double dab = ddot(p - qab, p - qab), dac = ddot(p - qac, p - qac), dbc = ddot(p - qbc, p - qbc);
        if (dab <= dac && dab <= dbc) return {to_float(qab), float(wab), 0};
        if (dac <= dbc) return {to_float(qac), 0, float(wac)};
        return {to_float(qbc), float(1 - wbc), float(wbc)};
    }
    const double v = vb / sum, w = vc / sum;
    return {to_float(a + ab * v + ac * w), float(v), float(w)};
}

}  // namespace thicket
