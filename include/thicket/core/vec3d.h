#pragma once
/// Small 3-vector of doubles: what the shape kernels compute in, the coordinates of
/// `precision=double` structures and of scenes whose files give double vertices
/// (TriangleMesh::positions_double).
#include <algorithm>
#include <cmath>

#include "thicket/core/vec3.h"

namespace thicket {

struct DVec3 {
    double x = 0, y = 0, z = 0;

    constexpr DVec3() = default;
    constexpr DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit DVec3(Vec3 v) : x(v.x), y(v.y), z(v.z) {}

    constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr DVec3 operator+(DVec3 b) const { return {x + b.x, y + b.y, z + b.z}; }
    constexpr DVec3 operator-(DVec3 b) const { return {x - b.x, y - b.y, z - b.z}; }
    constexpr DVec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr DVec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    constexpr DVec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 to_float() const { return {float(x), float(y), float(z)}; }
    constexpr bool operator==(const DVec3&) const = default;
};

constexpr double dot(DVec3 a, DVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr DVec3 cross(DVec3 a, DVec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(DVec3 v) { return std::sqrt(dot(v, v)); }
inline bool is_finite(DVec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline DVec3 normalize(DVec3 v) { return v / length(v); }

constexpr DVec3 min(DVec3 a, DVec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
constexpr DVec3 max(DVec3 a, DVec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

/// The name the double-precision structures and meshes use.
using Vec3d = DVec3;

}  // namespace thicket
