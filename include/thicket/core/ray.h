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
struct Ray {
    Vec3 org;
    float tmin = 0.0f;
    Vec3 dir;
    float tmax = kInfinity;
};

/// The ray of 8 floats (origin x y z, direction x y z, tmin, tmax) as ray files and bindings hold
/// them. False, and `ray` untouched, for a ray without meaning: a non-finite origin or direction,
/// a zero direction, a NaN or reversed interval. Such rays are to be answered as misses, not
/// traced: every traversal assumes a finite origin and a non-zero direction.
inline bool make_ray(const float* r, Ray& ray) {
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(r[i])) return false;
    if (std::isnan(r[6]) || std::isnan(r[7]) || r[6] > r[7]) return false;
    if (r[3] == 0.0f && r[4] == 0.0f && r[5] == 0.0f) return false;
    ray.org = {r[0], r[1], r[2]};
    ray.dir = {r[3], r[4], r[5]};
    ray.tmin = r[6];
    ray.tmax = r[7];
    return true;
}

/// Closest-hit record. prim == kNoPrim means no hit. (u, v) are the primitive's surface
/// parameters; for triangles the barycentric weights of vertices 1 and 2.
struct Hit {
    float t = kInfinity;
    float u = 0.0f;
    float v = 0.0f;
    uint32_t prim = kNoPrim;

    constexpr bool found() const { return prim != kNoPrim; }
};
// The layout is part of the contract: the Python module transposes four hits at a time with SSE,
// and the .npy hit records (t, prim, u, v) are written from it.
static_assert(sizeof(Hit) == 16 && offsetof(Hit, t) == 0 && offsetof(Hit, u) == 4 && offsetof(Hit, v) == 8 &&
                  offsetof(Hit, prim) == 12,
              "Hit is t u v prim, 16 bytes");

/// Starts a closest-hit query: the search interval's far end is the ray's tmax.
constexpr Hit miss_for(const Ray& ray) { return Hit{ray.tmax, 0.0f, 0.0f, kNoPrim}; }

/// Per-ray work counters. Structures take a counting policy as a template argument, so the
/// non-counting path compiles to nothing (see NoCounters).
struct RayCounters {
    uint64_t nodes = 0;  ///< interior and leaf nodes (or cells) visited
    uint64_t prims = 0;  ///< primitive intersection tests
    void node() { ++nodes; }
    void prim() { ++prims; }
    RayCounters& operator+=(const RayCounters& o) { nodes += o.nodes; prims += o.prims; return *this; }
};

struct NoCounters {
    constexpr void node() {}
    constexpr void prim() {}
};

}  // namespace thicket
