#pragma once
/// Plane-by-plane slab arithmetic for structures that clip the ray's interval one axis plane at
/// a time (BIH clip planes, octree cells) instead of testing whole boxes. Every distance is
/// formed and widened exactly as ray_box_entry() forms and widens it, so the intervals these
/// structures compute always contain the hits hit_within_bounds() accepts: a primitive whose box
/// lies on the inner side of a plane can only report hits on the inner side of the widened
/// distance to that plane (the products and the widening are both monotone in the plane).
#include "thicket/core/aabb.h"
#include "thicket/core/ray_box.h"

namespace thicket {

/// Distance along the ray to the plane x[axis] = plane: the product ray_box_entry() forms.
/// +-inf or NaN when the ray is parallel to the plane (NaN: it lies in the plane).
inline float plane_distance(const RayBoxQuery& q, int axis, float plane) {
    return (plane - q.org[axis]) * q.inv_dir[axis];
}

/// A lower end of an interval moved outward exactly as ray_box_entry() moves a near distance.
inline float widen_near(float t) { return t * (t > 0.0f ? (1.0f - kSlabSlack) : (1.0f + kSlabSlack)); }

/// An upper end moved outward exactly as ray_box_entry() moves a far distance.
inline float widen_far(float t) {
    constexpr float grow = 1.0f + 2.0f * rounding_gamma(3) + kSlabSlack;
    constexpr float shrink = 1.0f - 2.0f * rounding_gamma(3) - kSlabSlack;
    return t * (t > 0.0f ? grow : shrink);
}

struct SlabInterval {
    float t0 = kInfinity, t1 = -kInfinity;  ///< empty (t0 > t1) when the ray misses
    bool empty() const { return !(t0 <= t1); }
};

/// The ray's interval through `box` clipped to [tmin, tmax], widened as ray_box_entry() widens it
/// (its t0 is what ray_box_entry() returns); empty when the ray misses. An axis whose distances
/// are NaN (the ray lies in a face of the box) does not narrow the interval.
inline SlabInterval ray_box_interval(const RayBoxQuery& q, const Aabb& box, float tmin, float tmax) {
    const Vec3* planes[2] = {&box.min, &box.max};
    float t0 = tmin, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        const float near_t = widen_near(plane_distance(q, a, (*planes[q.neg[a]])[a]));
        const float far_t = widen_far(plane_distance(q, a, (*planes[1 - q.neg[a]])[a]));
        t0 = near_t > t0 ? near_t : t0;  // a NaN candidate is dropped
        t1 = far_t < t1 ? far_t : t1;
    }
    return t0 <= t1 ? SlabInterval{t0, t1} : SlabInterval{};
}

}  // namespace thicket
