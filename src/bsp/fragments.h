#pragma once
// What the BSP builder's skeleton needs to know about fragments, shared by both kinds: where a
// fragment lies relative to a plane, and the plane equation evaluated in double.
#include <array>
#include <cstddef>
#include <cstdint>

#include "thicket/core/aabb.h"

#include "thicket/bsp/node.h"

namespace thicket::bsp_build {

using P3 = std::array<double, 3>;

enum class Side : uint8_t { Back, Front, Straddle };

/// Where a fragment goes: wholly to one side, or cut in two; `in_plane` when it lies in the
/// plane (within the builder's tolerance) and was sent to `side` by the in-plane rule.
struct Placement {
    Side side = Side::Back;
    bool in_plane = false;
};

/// dot(normal, x) - offset in double (the float plane, evaluated without further rounding of note).
inline double plane_distance(const BspPlane& p, const P3& x) {
    return double(p.normal.x) * x[0] + double(p.normal.y) * x[1] + double(p.normal.z) * x[2] - double(p.offset);
}

inline P3 to_p3(const Vec3& v) { return {double(v.x), double(v.y), double(v.z)}; }

/// The box of points p[0 .. n), in float (to nearest: boxes serve cost estimates only).
inline Aabb points_box(const P3* p, size_t n) {
    Aabb b;
    for (size_t i = 0; i < n; ++i) b.grow(Vec3(float(p[i][0]), float(p[i][1]), float(p[i][2])));
    return b;
}

/// Which sides of the plane points p[0 .. n) reach beyond `tolerance`: bit 0 back, bit 1 front.
inline int sides_reached(const BspPlane& plane, const P3* p, size_t n, double tolerance) {
    int sides = 0;
    for (size_t i = 0; i < n; ++i) {
        const double d = plane_distance(plane, p[i]);
        sides |= (d < -tolerance ? 1 : 0) | (d > tolerance ? 2 : 0);
    }
    return sides;
}

}  // namespace thicket::bsp_build
