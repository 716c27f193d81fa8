#pragma once
/// Axis-aligned bounding box; the empty box has min = +inf, max = -inf so that growing works.
#include <cmath>
#include <limits>
#include <type_traits>

#include "thicket/core/vec3.h"

namespace thicket {

/// Aabb (float) bounds every structure's nodes; AabbD (double) the `precision=double` ones'.
template <class S>
struct AabbT {
    Vec3T<S> min{std::numeric_limits<S>::infinity()};
    Vec3T<S> max{-std::numeric_limits<S>::infinity()};

    constexpr void grow(Vec3T<S> p) { min = thicket::min(min, p); max = thicket::max(max, p); }
    constexpr void grow(const AabbT& b) { min = thicket::min(min, b.min); max = thicket::max(max, b.max); }
    constexpr bool empty() const { return min.x > max.x || min.y > max.y || min.z > max.z; }
    constexpr Vec3T<S> extent() const { return max - min; }
    constexpr Vec3T<S> center() const { return (min + max) * S(0.5); }
    /// Surface area; 0 for an empty box (so empty children never attract SAH cost).
    constexpr S area() const {
        if (empty()) return 0;
        Vec3T<S> e = extent();
        return S(2) * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    /// Half the surface area: what SAH ratios need, one multiply cheaper.
    constexpr S half_area() const {
        if (empty()) return 0;
        Vec3T<S> e = extent();
        return e.x * e.y + e.y * e.z + e.z * e.x;
    }
    constexpr bool contains(Vec3T<S> p) const {
        return p.x >= min.x && p.y >= min.y && p.z >= min.z && p.x <= max.x && p.y <= max.y && p.z <= max.z;
    }
};
using Aabb = AabbT<float>;
using AabbD = AabbT<double>;

/// The common part of two boxes (empty if they do not overlap).
template <class S>
constexpr AabbT<S> intersection(const AabbT<S>& a, const std::type_identity_t<AabbT<S>>& b) {
    AabbT<S> r;
    r.min = thicket::max(a.min, b.min);
    r.max = thicket::min(a.max, b.max);
    if (r.empty()) return AabbT<S>{};
    return r;
}

/// The smallest float box holding `b` (rounded outward): what a float builder may split on
/// without a primitive ever leaving its node's double box.
inline Aabb outward_float_box(const AabbD& b) {
    if (b.empty()) return Aabb{};
    Aabb f;
    for (int a = 0; a < 3; ++a) {
        float lo = float(b.min[a]), hi = float(b.max[a]);
        if (double(lo) > b.min[a]) lo = std::nextafter(lo, -std::numeric_limits<float>::infinity());
        if (double(hi) < b.max[a]) hi = std::nextafter(hi, std::numeric_limits<float>::infinity());
        f.min[a] = lo;
        f.max[a] = hi;
    }
    return f;
}

}  // namespace thicket
