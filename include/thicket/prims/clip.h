#pragma once
/// Clipping a triangle to a box (Sutherland-Hodgman against the six slabs): the exact bounds of
/// the part of a triangle inside a voxel, which "perfect split" kD-trees and BSP fragments need.
#include <array>
#include <cmath>
#include <utility>

#include "thicket/core/aabb.h"

namespace thicket {

/// Bounds of the part of triangle (a, b, c) inside `box`; empty if none. Flat triangles lying in
/// a face of the box keep that face (the box is closed). Computed in double so that vertices far
/// from the box do not lose the clipped corner to rounding; the result is widened to enclose it
/// in float and intersected with `box`.
inline Aabb clip_triangle_to_box(Vec3 a, Vec3 b, Vec3 c, const Aabb& box) {
    Aabb whole;
    whole.grow(a);
    whole.grow(b);
    whole.grow(c);
    // Common case in deep trees: nothing to clip (or nothing left).
    if (box.contains(whole.min) && box.contains(whole.max)) return whole;
    if (intersection(whole, box).empty()) return Aabb{};
    struct P {
        double v[3];
    };
    // A triangle clipped by 6 planes has at most 3 + 6 vertices.
    std::array<P, 12> buffers[2];
    P* poly = buffers[0].data();
    P* next = buffers[1].data();  // ping-pong: no copy per plane
    int n = 3;
    poly[0] = {{a.x, a.y, a.z}};
    poly[1] = {{b.x, b.y, b.z}};
    poly[2] = {{c.x, c.y, c.z}};
    for (int axis = 0; axis < 3 && n > 0; ++axis) {
        for (int side = 0; side < 2 && n > 0; ++side) {
            const double plane = side == 0 ? box.min[axis] : box.max[axis];
            auto inside = [&](const P& p) { return side == 0 ? p.v[axis] >= plane : p.v[axis] <= plane; };
            int m = 0;
            for (int i = 0; i < n; ++i) {
                const P& cur = poly[i];
                const P& nxt = poly[(i + 1) % n];
                const bool ci = inside(cur), ni = inside(nxt);
                if (ci) next[m++] = cur;
                if (ci != ni) {
                    const double s = (plane - cur.v[axis]) / (nxt.v[axis] - cur.v[axis]);
                    P q;
                    for (int k = 0; k < 3; ++k) q.v[k] = cur.v[k] + s * (nxt.v[k] - cur.v[k]);
                    q.v[axis] = plane;  // exactly on the plane, whatever the rounding
                    next[m++] = q;
                }
            }
            n = m;
            std::swap(poly, next);
        }
    }
    if (n == 0) return Aabb{};
    Aabb r;
    for (int i = 0; i < n; ++i) {
        Vec3 lo, hi;
        for (int k = 0; k < 3; ++k) {
            const float f = float(poly[i].v[k]);
            // Round outwards so the float box encloses the double polygon.
            lo[k] = double(f) > poly[i].v[k] ? std::nextafter(f, -INFINITY) : f;
            hi[k] = double(f) < poly[i].v[k] ? std::nextafter(f, INFINITY) : f;
        }
        r.grow(lo);
        r.grow(hi);
    }
    return intersection(r, box);
}

}  // namespace thicket
