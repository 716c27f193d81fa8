#pragma once
/// Robust ray/box slab test (Ize 2013, "Robust BVH Ray Traversal"), correct for axis-parallel
/// rays and for +0 and -0 direction components.
///
/// Why it is robust:
/// - The near and far planes are chosen per axis by the sign bit of 1/dir, so -0 (which gives
///   1/dir = -inf) picks the planes the same way the IEEE infinities point.
/// - 0 * inf = NaN arises only when the origin lies exactly on a slab plane of an axis the ray is
///   parallel to. The running max/min are written as `a > b ? a : b` with the candidate first,
///   which drops a NaN candidate: such an axis simply does not narrow the interval (the ray lies
///   in the slab's closed boundary, so the box must not be culled).
/// - The far distance is scaled by 1 + 2*gamma(3) so that rounding in (b - o) * inv can never
///   cull a box the exact ray touches.
#include <cmath>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

namespace thicket {

/// Conservative rounding bound gamma(n) = n*eps / (1 - n*eps) for float, eps = 2^-24.
constexpr float rounding_gamma(int n) {
    constexpr float eps = 0.5f * 1.1920928955078125e-07f;
    return (n * eps) / (1.0f - n * eps);
}

/// Per-ray data of the slab test, computed once per ray.
struct RayBoxQuery {
    Vec3 org;
    Vec3 inv_dir;   ///< 1/dir per axis; exactly +-inf for a +-0 component
    int neg[3];     ///< 1 where inv_dir's sign bit is set: the near plane is the box's max

    explicit RayBoxQuery(const Ray& r) : org(r.org), inv_dir(1.0f / r.dir.x, 1.0f / r.dir.y, 1.0f / r.dir.z) {
        for (int a = 0; a < 3; ++a) neg[a] = std::signbit(inv_dir[a]) ? 1 : 0;
    }
};

/// Relative slack on both ends of every slab interval, beyond Ize's rounding bound. Triangle
/// tests' own t can be off by ~1e-5 relative (Moller-Trumbore on a ray through a shared vertex,
/// where o - v0 is long against the edges: seen on sibenik). A box entered just beyond the current
/// hit must still be visited, or a structure reports a different primitive than brute force for
/// what is really one point; the slack costs almost no culling.
inline constexpr float kSlabSlack = 1e-4f;

/// Distance at which the ray enters `box` within [tmin, tmax], or +inf if it misses.
/// `box_min`/`box_max` are passed separately so node layouts need not be Aabb.
inline float ray_box_entry(const RayBoxQuery& q, const Vec3& box_min, const Vec3& box_max, float tmin, float tmax) {
    constexpr float grow = 1.0f + 2.0f * rounding_gamma(3) + kSlabSlack;
    constexpr float shrink = 1.0f - 2.0f * rounding_gamma(3) - kSlabSlack;
    const Vec3* planes[2] = {&box_min, &box_max};
    float t0 = tmin, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        float near_t = ((*planes[q.neg[a]])[a] - q.org[a]) * q.inv_dir[a];
        float far_t = ((*planes[1 - q.neg[a]])[a] - q.org[a]) * q.inv_dir[a];
        // Widen outward whatever the sign; +-inf stay infinite and NaN stays NaN.
        near_t *= near_t > 0.0f ? (1.0f - kSlabSlack) : (1.0f + kSlabSlack);
        far_t *= far_t > 0.0f ? grow : shrink;
        t0 = near_t > t0 ? near_t : t0;  // NaN candidate is dropped (see file comment)
        t1 = far_t < t1 ? far_t : t1;
    }
    return t0 <= t1 ? t0 : kInfinity;
}

inline float ray_box_entry(const RayBoxQuery& q, const Aabb& box, float tmin, float tmax) {
    return ray_box_entry(q, box.min, box.max, tmin, tmax);
}

}  // namespace thicket


namespace thicket {

/// The consistency rule every primitive applies to its hits: distance t counts only if it lies
/// in the ray's interval through the primitive's bounds (widened by kSlabSlack), the interval
/// every structure tests on the way down. A box hierarchy then never misses a hit that brute
/// force reports. A genuine hit lies inside its bounds and the slack exceeds the tests' rounding,
/// so only ill-conditioned results are rejected (e.g. a ray grazing a triangle almost parallel
/// to it, reported at its vertex but 2 units off along the ray).
inline bool hit_within_bounds(const Ray& ray, float t, const Aabb& bounds) {
    return ray_box_entry(RayBoxQuery(ray), bounds, t, t) != kInfinity;
}

}  // namespace thicket
