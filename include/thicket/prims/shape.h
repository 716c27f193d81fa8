#pragma once
/// The contract of a complex primitive ("shape": sphere, torus, Bezier patch, implicit surface,
/// fractal, subdivision surface). A shape kernel is a plain struct answering three questions;
/// the mixed primitive set (issue 5) holds any number of them next to triangles, so every
/// acceleration structure can hold them.
#include <concepts>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

namespace thicket {

/// What a shape test reports: the ray parameter and the shape's own surface parameters.
struct ShapeHit {
    float t = 0.0f;
    float u = 0.0f, v = 0.0f;
};

template <class S>
concept ShapeKernel = requires(const S& s, const Ray& ray, float tmax, ShapeHit& hit, Vec3 p, float u, float v) {
    /// Conservative bounds of the whole surface.
    { s.bounds() } -> std::same_as<Aabb>;
    /// First surface crossing with t in [ray.tmin, tmax]; fills hit and returns true, or false.
    { s.intersect(ray, tmax, hit) } -> std::same_as<bool>;
    /// Unit outward normal at a surface point p with parameters (u, v) from intersect (finite,
    /// also at degenerate points such as a Bezier patch's collapsed corner).
    { s.normal(p, u, v) } -> std::same_as<Vec3>;
};

}  // namespace thicket
