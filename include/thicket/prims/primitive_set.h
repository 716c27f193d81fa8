#pragma once
/// What an acceleration structure needs from its primitives. Any type that models PrimitiveSet
/// (triangles, spheres, a mixture) can be held by every structure.
#include <concepts>
#include <cstddef>
#include <cstdint>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"
#include "thicket/prims/clip.h"

namespace thicket {

template <class P>
concept PrimitiveSet = requires(const P& p, uint32_t i, const Ray& r, Hit& h) {
    { p.size() } -> std::convertible_to<size_t>;
    { p.bytes() } -> std::convertible_to<size_t>;
    { p.bounds(i) } -> std::same_as<Aabb>;
    { p.centroid(i) } -> std::same_as<Vec3>;
    { p.intersect(i, r, h) } -> std::same_as<bool>;  // closest-hit update within [r.tmin, h.t]
    { p.occludes(i, r) } -> std::same_as<bool>;      // any hit within [r.tmin, r.tmax]
};

/// Optional hooks a primitive set may offer; structures call these free functions, which fall
/// back to what every set has, so any PrimitiveSet works in every structure:
///   Aabb clip(i, box)                 exact bounds of the part of primitive i inside box
///   std::array<Vec3, 3> triangle(i)   the vertices, if every primitive of the set is a triangle

/// Bounds of the part of primitive i inside `box` (space-partitioning builders: perfect splits).
/// Falls back to bounds(i) intersected with box, which is conservative.
template <PrimitiveSet P>
Aabb clipped_bounds(const P& prims, uint32_t i, const Aabb& box) {
    if constexpr (requires { { prims.clip(i, box) } -> std::same_as<Aabb>; })
        return prims.clip(i, box);
    else
        return intersection(prims.bounds(i), box);
}

/// Whether the set is all triangles with vertices reachable by triangle(i) (BSP autopartition
/// takes its planes from them; other sets fall back to axis-aligned planes from the bounds).
template <class P>
inline constexpr bool kHasTriangles = requires(const P& p, uint32_t i) { p.triangle(i); };

/// Whether the set answers rays in double (TrianglesD, whose boxes are AabbD): what the
/// `precision=double` structures hold. Such a set models PrimitiveSet's requirements with
/// RayD, HitD, AabbD and Vec3d in place of the float types.
template <class P>
inline constexpr bool kDoublePrimitives = requires(const P& p, uint32_t i) {
    { p.bounds(i) } -> std::same_as<AabbD>;
};

}  // namespace thicket
