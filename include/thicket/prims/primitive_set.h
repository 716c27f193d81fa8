#pragma once
/// What an acceleration structure needs from its primitives. Any type that models PrimitiveSet
/// (triangles, spheres, a mixture) can be held by every structure.
#include <concepts>
#include <cstddef>
#include <cstdint>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

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

}  // namespace thicket
