#pragma once
/// Axis-aligned bounding box; the empty box has min = +inf, max = -inf so that growing works.
#include <limits>

#include "thicket/core/vec3.h"

namespace thicket {

struct Aabb {
    Vec3 min{std::numeric_limits<float>::infinity()};
    Vec3 max{-std::numeric_limits<float>::infinity()};

    constexpr void grow(Vec3 p) { min = thicket::min(min, p); max = thicket::max(max, p); }
    constexpr void grow(const Aabb& b) { min = thicket::min(min, b.min); max = thicket::max(max, b.max); }
    constexpr bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    constexpr Vec3 extent() const { return max - min; }
    constexpr Vec3 center() const { return (min + max) * 0.5f; }
    /// Surface area; 0 for an empty box (so empty children never attract SAH cost).
    constexpr float area() const {
        if (empty()) return 0.0f;
        Vec3 e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    /// Half the surface area: what SAH ratios need, one multiply cheaper.
    constexpr float half_area() const {
        if (empty()) return 0.0f;
        Vec3 e = extent();
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
    constexpr bool contains(Vec3 p) const {
        return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y && p.z <= max.z;
    }
};

/// The common part of two boxes (empty if they do not overlap).
constexpr Aabb intersection(const Aabb& a, const Aabb& b) {
    Aabb r;
    r.min = thicket::max(a.min, b.min);
    r.max = thicket::min(a.max, b.max);
    if (r.empty()) return Aabb{};
    return r;
}

}  // namespace thicket
