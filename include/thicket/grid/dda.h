#pragma once
/// 3D-DDA (Amanatides & Woo 1987): walks the cells of a GridFrame in the order a ray pierces
/// them. Robust where the textbook version is not:
/// - the start cell comes from the entry point computed in double and clamped into the grid, so
///   a point rounded just outside (or NaN) still gives a valid cell;
/// - an axis the ray does not move along (a +0 or -0 component, or one so small that 1/d is
///   infinite, or NaN) never steps: its next crossing is +inf, so no 0 * inf = NaN appears;
/// - each crossing distance is computed afresh from the plane's index, base + k * delta, instead
///   of accumulating tDelta step after step, so error does not grow with the cells walked.
/// The walk always ends: every step moves one axis one cell towards the grid's side.
#include <cmath>
#include <cstdint>

#include "thicket/core/ray.h"
#include "thicket/grid/frame.h"

namespace thicket {

/// What the DDA needs of a ray, computed once per ray.
struct DdaRay {
    Vec3 org, dir, inv_dir;
    int step[3];      ///< +1, -1, or 0 for an axis the ray does not move along
    uint32_t up[3];   ///< 1 where step is +1: the exit plane of cell c is plane c + up

    explicit DdaRay(const Ray& r) : org(r.org), dir(r.dir) {
        for (int a = 0; a < 3; ++a) {
            const float inv = 1.0f / r.dir[a];
            const bool moves = r.dir[a] != 0.0f && std::isfinite(inv);
            inv_dir[a] = moves ? inv : 0.0f;
            step[a] = moves ? (r.dir[a] > 0.0f ? 1 : -1) : 0;
            up[a] = step[a] > 0 ? 1 : 0;
        }
    }
};

struct Dda {
    uint32_t cell[3];
    uint32_t index;   ///< linear index of the current cell
    float next[3];    ///< distance at which the ray crosses the current cell's exit plane per axis
    float base[3];    ///< distance to the frame's plane 0 per axis
    float delta[3];   ///< distance from one plane to the next per axis (signed like the direction)

    /// Starts at the cell holding the ray's point at distance t (clamped into the frame).
    [[gnu::always_inline]] Dda(const GridFrame& f, const DdaRay& r, float t) {
        for (int a = 0; a < 3; ++a) {
            cell[a] = f.clamp_index(a, double(r.org[a]) + double(r.dir[a]) * double(t));
            base[a] = (f.min[a] - r.org[a]) * r.inv_dir[a];
            delta[a] = f.cell[a] * r.inv_dir[a];
            next[a] = r.step[a] == 0 ? kInfinity : crossing(r, a);
        }
        index = f.index(cell[0], cell[1], cell[2]);
    }

    /// Leaves the current cell for the next one, unless the walk is over: when the current
    /// cell's exit distance is not below `far` (the nearest hit so far, or the ray's tmax: what
    /// lies beyond cannot matter) or the next cell is outside the frame. Returns whether it moved.
    /// The axis choice is spelled out per axis so that next[] stays in registers.
    [[gnu::always_inline]] bool step(const GridFrame& f, const DdaRay& r, float far) {
        if (next[0] < next[1]) return next[0] < next[2] ? advance<0>(f, r, far) : advance<2>(f, r, far);
        return next[1] < next[2] ? advance<1>(f, r, far) : advance<2>(f, r, far);
    }

private:
    /// Moves across axis A's exit plane (see step()).
    template <int A>
    [[gnu::always_inline]] bool advance(const GridFrame& f, const DdaRay& r, float far) {
        if (!(next[A] < far)) return false;                // also false for NaN and for inf == inf
        const uint32_t c = cell[A] + uint32_t(r.step[A]);  // wraps below 0: caught by the test
        if (c >= f.res[A] || r.step[A] == 0) return false;
        cell[A] = c;
        index += r.step[A] > 0 ? f.stride[A] : 0u - f.stride[A];
        next[A] = crossing(r, A);
        return true;
    }

    float crossing(const DdaRay& r, int a) const { return base[a] + float(cell[a] + r.up[a]) * delta[a]; }
};

/// The walk every grid level does: the cells of `frame` from the one holding the ray's point at
/// t_enter, in order. visit(const Dda&) handles the current cell and returns true to end the walk
/// (an any-hit query found something); the walk also ends when far() (the nearest hit so far, or
/// the ray's tmax) lies within the current cell, or the ray leaves the frame. Returns whether
/// visit ended it.
template <class Far, class Visit>
[[gnu::always_inline]] inline bool walk_cells(const GridFrame& frame, const DdaRay& r, float t_enter, Far&& far,
                                              Visit&& visit) {
    Dda dda(frame, r, t_enter);
    while (true) {
        if (visit(static_cast<const Dda&>(dda))) return true;
        if (!dda.step(frame, r, far())) return false;
    }
}

}  // namespace thicket
