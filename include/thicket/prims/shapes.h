#pragma once
/// The list of shape kernels a scene can hold, and the few operations on "any shape" that the
/// scene and the mixed primitive set need.
///
/// Adding a kernel (a struct modeling ShapeKernel, see shape.h):
///   1. include its header below and append its type to `Shape`;
///   2. add its parser to the table in src/scene/json_shapes.cpp;
///   3. document its JSON fields, (u, v) and normal in docs/shapes.md.
/// Give it `static constexpr const char* kName` (the JSON "type"), and keep it a plain struct of
/// floats without padding, or give it `uint64_t hash(uint64_t seed) const` for the scene's
/// fingerprint. Nothing else changes: every structure holds it through MixedPrimitives.
#include <cstdint>
#include <type_traits>
#include <variant>

#include "thicket/core/hash.h"
#include "thicket/prims/bezier.h"
#include "thicket/prims/fractal.h"
#include "thicket/prims/implicit.h"
#include "thicket/prims/shape.h"
#include "thicket/prims/sphere.h"
#include "thicket/prims/subdivision.h"
#include "thicket/prims/torus.h"

namespace thicket {

using Shape = std::variant<Sphere, Torus, BezierPatch, SubdivisionSurface, Implicit, Blobs, Julia, Mandelbulb>;

/// The JSON "type" name of kernel S ("shape" when it has none).
template <class S>
constexpr const char* shape_type_name() {
    if constexpr (requires { S::kName; })
        return S::kName;
    else
        return "shape";
}

inline const char* shape_name(const Shape& s) {
    return std::visit([](const auto& k) { return shape_type_name<std::decay_t<decltype(k)>>(); }, s);
}

inline Aabb shape_bounds(const Shape& s) {
    return std::visit([](const auto& k) { return k.bounds(); }, s);
}

/// Unit outward normal at p with the hit's (u, v).
inline Vec3 shape_normal(const Shape& s, Vec3 p, float u, float v) {
    return std::visit([&](const auto& k) { return k.normal(p, u, v); }, s);
}

/// FNV-1a of the kernel's type index and its parameters (its bytes, or its own hash()).
inline uint64_t shape_hash(const Shape& s, uint64_t h) {
    const uint64_t type = s.index();
    h = fnv1a(&type, sizeof type, h);
    return std::visit(
        [h](const auto& k) -> uint64_t {
            using S = std::decay_t<decltype(k)>;
            if constexpr (requires { { k.hash(h) } -> std::convertible_to<uint64_t>; }) {
                return k.hash(h);
            } else {
                static_assert(std::is_trivially_copyable_v<S> && sizeof(S) % sizeof(float) == 0,
                              "give the kernel a hash(seed) member, or make it a plain struct of floats");
                return fnv1a(&k, sizeof k, h);
            }
        },
        s);
}

namespace detail {
template <class V>
struct AllKernels;
template <class... S>
struct AllKernels<std::variant<S...>> : std::bool_constant<(ShapeKernel<S> && ...)> {};
}  // namespace detail
static_assert(detail::AllKernels<Shape>::value, "every alternative of Shape must model ShapeKernel");

}  // namespace thicket
