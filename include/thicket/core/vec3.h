#pragma once
/// Small 3-vector: Vec3 (float) is the one arithmetic type every structure speaks; Vec3d (double)
/// is what the shape kernels compute in, the coordinates of `precision=double` structures and of
/// scenes whose files give double vertices (TriangleMesh::positions_double). One template, so the
/// two precisions cannot drift apart.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace thicket {

template <class S>
struct Vec3T {
    S x = 0, y = 0, z = 0;

    constexpr Vec3T() = default;
    constexpr Vec3T(S x_, S y_, S z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3T(S s) : x(s), y(s), z(s) {}
    /// The other precision's vector, converted component by component (rounded to nearest).
    template <class O>
        requires(!std::is_same_v<O, S>)
    constexpr explicit Vec3T(const Vec3T<O>& v) : x(S(v.x)), y(S(v.y)), z(S(v.z)) {}

    constexpr S operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr S& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3T operator+(Vec3T b) const { return {x + b.x, y + b.y, z + b.z}; }
    constexpr Vec3T operator-(Vec3T b) const { return {x - b.x, y - b.y, z - b.z}; }
    constexpr Vec3T operator*(Vec3T b) const { return {x * b.x, y * b.y, z * b.z}; }
    constexpr Vec3T operator/(Vec3T b) const { return {x / b.x, y / b.y, z / b.z}; }
    constexpr Vec3T operator*(S s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3T operator/(S s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3T operator-() const { return {-x, -y, -z}; }
    constexpr Vec3T& operator+=(Vec3T b) { x += b.x; y += b.y; z += b.z; return *this; }
    constexpr Vec3T& operator-=(Vec3T b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
    constexpr Vec3T& operator*=(S s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3T&) const = default;
    /// This vector rounded to float, each component to nearest.
    constexpr Vec3T<float> to_float() const { return {float(x), float(y), float(z)}; }
};

using Vec3 = Vec3T<float>;
using Vec3d = Vec3T<double>;

// The functions are declared inline, as constexpr ones are: GCC inlines a function template
// not so declared less eagerly (core/triangle.h says what that cost).
// The second operand of each binary function is not deduced, so it may be written braced
// (dot(n, {0, 0, 1})) and a scalar of the other precision converts as it did before.
template <class S>
using Vec3Same = std::type_identity_t<Vec3T<S>>;

template <class S>
constexpr Vec3T<S> operator*(std::type_identity_t<S> s, Vec3T<S> v) { return v * s; }
template <class S>
constexpr S dot(Vec3T<S> a, Vec3Same<S> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class S>
constexpr Vec3T<S> cross(Vec3T<S> a, Vec3Same<S> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class S>
inline S length(Vec3T<S> v) { return std::sqrt(dot(v, v)); }
template <class S>
inline Vec3T<S> normalize(Vec3T<S> v) { return v / length(v); }
template <class S>
constexpr Vec3T<S> min(Vec3T<S> a, Vec3Same<S> b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
template <class S>
constexpr Vec3T<S> max(Vec3T<S> a, Vec3Same<S> b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
/// No component infinite or NaN.
template <class S>
inline bool is_finite(Vec3T<S> v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
template <class S>
inline Vec3T<S> abs(Vec3T<S> v) { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }
template <class S>
constexpr S max_component(Vec3T<S> v) { return std::max(v.x, std::max(v.y, v.z)); }
/// Index (0, 1, 2) of the largest component; ties go to the lower axis.
template <class S>
constexpr int max_axis(Vec3T<S> v) { return (v.x >= v.y && v.x >= v.z) ? 0 : (v.y >= v.z ? 1 : 2); }

}  // namespace thicket
