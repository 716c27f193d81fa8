#pragma once
/// Closest points: on a triangle (with its barycentrics) and the distance from a point to a box,
/// the two pieces every closest-point query is made of.
#include <algorithm>
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

/// Squared distance from p to the box (0 inside it).
inline float distance2_to_box(const Vec3& p, const Aabb& b) {
    float d2 = 0.0f;
    for (int a = 0; a < 3; ++a) {
        const float d = std::max({b.min[a] - p[a], 0.0f, p[a] - b.max[a]});
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
/// Closest point of segment a + w (b - a), w in [0, 1], to p; `w` receives w.
inline Vec3 closest_point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b, float& w) {
    const Vec3 ab = b - a;
    const float len2 = dot(ab, ab);
    w = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
    return a + ab * w;
}
inline TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return {a, 0, 0};
    const Vec3 bp = p - b;
    const float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return {b, 1, 0};
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const float w = d1 / (d1 - d3);
        return {a + ab * w, w, 0};
    }
    const Vec3 cp = p - c;
    const float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return {c, 0, 1};
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const float w = d2 / (d2 - d6);
        return {a + ac * w, 0, w};
    }
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {b + (c - b) * w, 1 - w, w};
    }
    const float sum = va + vb + vc;
    if (!(sum > 0)) {
        // No interior (collinear corners; rounding can bring a needle here): its three segments.
        float wab, wac, wbc;
        const Vec3 qab = closest_point_on_segment(p, a, b, wab), qac = closest_point_on_segment(p, a, c, wac),
                   qbc = closest_point_on_segment(p, b, c, wbc);
        const float dab = dot(p - qab, p - qab), dac = dot(p - qac, p - qac), dbc = dot(p - qbc, p - qbc);
        if (dab <= dac && dab <= dbc) return {qab, wab, 0};
        if (dac <= dbc) return {qac, 0, wac};
        return {qbc, 1 - wbc, wbc};
    }
    const float v = vb / sum, w = vc / sum;
    return {a + ab * v + ac * w, v, w};
}

}  // namespace thicket
