#pragma once
/// Ray and hit records shared by every structure and primitive.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "thicket/core/vec3.h"

namespace thicket {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr uint32_t kNoPrim = 0xFFFFFFFFu;

/// A ray accepts hits with tmin <= t <= tmax; t is in units of dir's length (dir need not be unit).
/// Ray is the float ray every structure traces; RayD (double) is what `precision=double`
/// structures trace, for coordinates far from the origin.
template <class S>
struct RayT {
    Vec3T<S> org;
    S tmin = 0;
    Vec3T<S> dir;
    S tmax = std::numeric_limits<S>::infinity();
};
using Ray = RayT<float>;
using RayD = RayT<double>;

/// The ray of 8 scalars (origin x y z, direction x y z, tmin, tmax) as ray files and bindings hold
/// them. False, and `ray` untouched, for a ray without meaning: a non-finite origin or direction,
/// a zero direction, a NaN or reversed interval. Such rays are to be answered as misses, not
/// traced: every traversal assumes a finite origin and a non-zero direction.
template <class S>
inline bool make_ray(const S* r, RayT<S>& ray) {
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(r[i])) return false;
    if (std::isnan(r[6]) || std::isnan(r[7]) || r[6] > r[7]) return false;
    if (r[3] == 0 && r[4] == 0 && r[5] == 0) return false;
    ray.org = {r[0], r[1], r[2]};
    ray.dir = {r[3], r[4], r[5]};
    ray.tmin = r[6];
    ray.tmax = r[7];
    return true;
}

/// Closest-hit record. prim == kNoPrim means no hit. (u, v) are the primitive's surface
/// parameters; for triangles the barycentric weights of vertices 1 and 2.
template <class S>
struct HitT {
    S t = std::numeric_limits<S>::infinity();
    S u = 0;
    S v = 0;
    uint32_t prim = kNoPrim;

    constexpr bool found() const { return prim != kNoPrim; }
};
using Hit = HitT<float>;
using HitD = HitT<double>;
// The layout is part of the contract: the Python module transposes four hits at a time with SSE,
// and the .npy hit records (t, prim, u, v) are written from it.
static_assert(sizeof(Hit) == 16 && offsetof(Hit, t) == 0 && offsetof(Hit, u) == 4 && offsetof(Hit, v) == 8 &&
                  offsetof(Hit, prim) == 12,
              "Hit is t u v prim, 16 bytes");

/// A float ray widened exactly to double.
inline RayD to_double(const Ray& r) {
    const double inf = std::numeric_limits<double>::infinity();
    return {Vec3d(r.org), r.tmin == kInfinity ? inf : double(r.tmin), Vec3d(r.dir),
            r.tmax == kInfinity ? inf : double(r.tmax)};
}
/// The double hit rounded to float (t beyond float's range becomes +inf).
inline Hit to_hit(const HitD& h) { return {float(h.t), float(h.u), float(h.v), h.prim}; }

/// Starts a closest-hit query: the search interval's far end is the ray's tmax.
template <class S>
constexpr HitT<S> miss_for(const RayT<S>& ray) { return HitT<S>{ray.tmax, 0, 0, kNoPrim}; }

/// Per-ray work counters. Structures take a counting policy as a template argument, so the
/// non-counting path compiles to nothing (see NoCounters).
struct RayCounters {
    uint64_t nodes = 0;  ///< interior and leaf nodes (or cells) visited
    uint64_t prims = 0;  ///< primitive intersection tests
    /// Interior node visits by the children the ray entered there: 0, 1, 2, 3, 4, 5 or more
    /// (bvh8's counting kernels: how many ordering decisions a visit makes; others leave it 0).
    uint64_t entered[6] = {};
    void node() { ++nodes; }
    void prim() { ++prims; }
    RayCounters& operator+=(const RayCounters& o) {
        nodes += o.nodes;
        prims += o.prims;
        for (int k = 0; k < 6; ++k) entered[k] += o.entered[k];
        return *this;
    }
};

struct NoCounters {
    constexpr void node() {}
    constexpr void prim() {}
};

}  // namespace thicket
