#pragma once
/// Robust ray/box slab test (Ize 2013, "Robust BVH Ray Traversal"), correct for axis-parallel
/// rays and for +0 and -0 direction components, in float (every structure) and in double (the
/// `precision=double` structures): one template, so the two precisions cannot drift apart.
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
#include <limits>
#include <type_traits>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

namespace thicket {

/// Conservative rounding bound gamma(n) = n*eps / (1 - n*eps) of scalar S (float: eps = 2^-24).
template <class S = float>
constexpr S rounding_gamma(int n) {
    constexpr S eps = S(0.5) * std::numeric_limits<S>::epsilon();
    return (n * eps) / (S(1) - n * eps);
}

/// Per-ray data of the slab test, computed once per ray.
template <class S>
struct RayBoxQueryT {
    Vec3T<S> org;
    Vec3T<S> inv_dir;  ///< 1/dir per axis; exactly +-inf for a +-0 component
    int neg[3];        ///< 1 where inv_dir's sign bit is set: the near plane is the box's max

    explicit RayBoxQueryT(const RayT<S>& r) : org(r.org), inv_dir(S(1) / r.dir.x, S(1) / r.dir.y, S(1) / r.dir.z) {
        for (int a = 0; a < 3; ++a) neg[a] = std::signbit(inv_dir[a]) ? 1 : 0;
    }
};
using RayBoxQuery = RayBoxQueryT<float>;
using RayBoxQueryD = RayBoxQueryT<double>;

/// Relative slack on both ends of every slab interval, beyond Ize's rounding bound. Triangle
/// tests' own t can be off by ~1e-5 relative (Moller-Trumbore on a ray through a shared vertex,
/// where o - v0 is long against the edges: seen on sibenik). A box entered just beyond the current
/// hit must still be visited, or a structure reports a different primitive than brute force for
/// what is really one point; the slack costs almost no culling.
inline constexpr float kSlabSlack = 1e-4f;
/// The same in double: far below anything float could resolve, far above double's rounding of
/// the tests.
inline constexpr double kSlabSlackD = 1e-12;
template <class S>
inline constexpr S kSlabSlackOf = std::is_same_v<S, float> ? S(kSlabSlack) : S(kSlabSlackD);

/// Distance at which the ray enters the box [box_min, box_max] within [tmin, tmax], or +inf if
/// it misses. The corners are passed separately so node layouts need not be Aabb.
template <class S>
inline S ray_box_entry(const RayBoxQueryT<S>& q, const std::type_identity_t<Vec3T<S>>& box_min,
                       const std::type_identity_t<Vec3T<S>>& box_max, std::type_identity_t<S> tmin,
                       std::type_identity_t<S> tmax) {
    constexpr S slack = kSlabSlackOf<S>;
    constexpr S grow = S(1) + S(2) * rounding_gamma<S>(3) + slack;
    constexpr S shrink = S(1) - S(2) * rounding_gamma<S>(3) - slack;
    const Vec3T<S>* planes[2] = {&box_min, &box_max};
    S t0 = tmin, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        S near_t = ((*planes[q.neg[a]])[a] - q.org[a]) * q.inv_dir[a];
        S far_t = ((*planes[1 - q.neg[a]])[a] - q.org[a]) * q.inv_dir[a];
        // Widen outward whatever the sign; +-inf stay infinite and NaN stays NaN.
        near_t *= near_t > S(0) ? (S(1) - slack) : (S(1) + slack);
        far_t *= far_t > S(0) ? grow : shrink;
        t0 = near_t > t0 ? near_t : t0;  // NaN candidate is dropped (see file comment)
        t1 = far_t < t1 ? far_t : t1;
    }
    return t0 <= t1 ? t0 : std::numeric_limits<S>::infinity();
}

template <class S>
inline S ray_box_entry(const RayBoxQueryT<S>& q, const std::type_identity_t<AabbT<S>>& box,
                       std::type_identity_t<S> tmin, std::type_identity_t<S> tmax) {
    return ray_box_entry(q, box.min, box.max, tmin, tmax);
}

/// The consistency rule every primitive applies to its hits: distance t counts only if it lies
/// in the ray's interval through the primitive's bounds (widened by kSlabSlack), the interval
/// every structure tests on the way down. A box hierarchy then never misses a hit that brute
/// force reports. A genuine hit lies inside its bounds and the slack exceeds the tests' rounding,
/// so only ill-conditioned results are rejected (e.g. a ray grazing a triangle almost parallel
/// to it, reported at its vertex but 2 units off along the ray).
template <class S>
inline bool hit_within_bounds(const RayT<S>& ray, std::type_identity_t<S> t, const std::type_identity_t<AabbT<S>>& bounds) {
    return ray_box_entry(RayBoxQueryT<S>(ray), bounds, t, t) != std::numeric_limits<S>::infinity();
}

}  // namespace thicket
