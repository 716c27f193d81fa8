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

    /// The axis whose plane the ray crosses first; next[exit_axis()] is the current cell's exit.
    [[gnu::always_inline]] int exit_axis() const {
        return next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    }

    /// Moves to the neighbour across axis a; false when that leaves the frame (or the ray does
    /// not move along a: then every crossing is +inf and the walk is over).
    [[gnu::always_inline]] bool advance(const GridFrame& f, const DdaRay& r, int a) {
        const uint32_t c = cell[a] + uint32_t(r.step[a]);  // wraps below 0: caught by the test
        if (c >= f.res[a] || r.step[a] == 0) return false;
        cell[a] = c;
        index += r.step[a] > 0 ? f.stride[a] : 0u - f.stride[a];
        next[a] = crossing(r, a);
        return true;
    }

private:
    float crossing(const DdaRay& r, int a) const { return base[a] + float(cell[a] + r.up[a]) * delta[a]; }
};

}  // namespace thicket
