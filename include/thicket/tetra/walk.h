#pragma once
/// The geometry of walking a tetrahedral mesh: face planes computed the same way from both sides
/// of a face (its vertices in id order), and point location by a visibility walk.
#include <algorithm>
#include <cmath>

#include "thicket/tetra/mesh.h"

namespace thicket::tetra_detail {

/// The plane of face k of tetrahedron t as an outward normal `n` (unscaled) and a point `a` on
/// it (its lowest-id vertex). Every tetrahedron is stored positively oriented (the build makes
/// it so), so the outward side follows from k and the order of the face's vertices, never from
/// a rounded volume: both tetrahedra of a face get the same numbers, negated, even for slivers,
/// and a walk can never leave a tetrahedron through a face its neighbour calls an exit too.
inline void face_plane(const TetraMesh& m, uint32_t t, int k, Vec3d& n, Vec3d& a) {
    const uint32_t* v = &m.tets[size_t(t) * 4];
    uint32_t f[3];
    int j = 0;
    for (int i = 0; i < 4; ++i)
        if (i != k) f[j++] = v[i];
    // Outward for a positive tetrahedron with the face's vertices in tet order: +, -, +, -.
    bool flip = (k & 1) != 0;
    if (f[0] > f[1]) std::swap(f[0], f[1]), flip = !flip;
    if (f[1] > f[2]) std::swap(f[1], f[2]), flip = !flip;
    if (f[0] > f[1]) std::swap(f[0], f[1]), flip = !flip;
    a = m.points[f[0]];
    n = cross(m.points[f[1]] - a, m.points[f[2]] - a);
    if (flip) n = n * -1.0;
}

/// Six times the signed volume of tetrahedron (a, b, c, d): positive when d lies on the side of
/// (a, b, c) that cross(b - a, c - a) points to.
inline double orient(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d) { return dot(cross(b - a, c - a), d - a); }

/// How far outside face k of tetrahedron t the point p lies (> 0 outside), in units of the
/// face's normal length times distance.
inline double outside(const TetraMesh& m, uint32_t t, int k, const Vec3d& p) {
    Vec3d n, a;
    face_plane(m, t, k, n, a);
    return dot(n, p - a);
}

/// A tetrahedron near p to start walks from: the start grid's cell holding p (clamped).
inline uint32_t grid_start(const TetraMesh& m, const Vec3d& p) {
    if (m.grid_start.empty()) return 0;
    uint32_t cell[3];
    for (int a = 0; a < 3; ++a) {
        const double lo = m.box_min[a], hi = m.box_max[a];
        const double u = hi > lo ? (p[a] - lo) / (hi - lo) : 0.0;
        const double c = std::floor(u * m.grid_res);
        cell[a] = uint32_t(std::clamp(c, 0.0, double(m.grid_res - 1)));
    }
    return m.grid_start[(size_t(cell[2]) * m.grid_res + cell[1]) * m.grid_res + cell[0]];
}

/// The tetrahedron holding p (or, for p on a face or just outside the mesh by rounding, one
/// next to it): a visibility walk from `start`, stepping through a face p lies outside of, the
/// face tried first rotating so that no cycle can repeat forever; past a step budget, the
/// tetrahedron p lies least outside of, by a scan of them all. `steps` counts the walk.
template <class Count>
uint32_t locate(const TetraMesh& m, const Vec3d& p, uint32_t start, Count&& steps) {
    const size_t tets = m.tet_count();
    if (tets == 0) return kNoTet;
    uint32_t t = start < tets ? start : 0;
    const size_t budget = 64 + 8 * size_t(std::cbrt(double(tets))) * 8;
    for (size_t step = 0; step < budget; ++step) {
        steps();
        int next = -1;
        for (int i = 0; i < 4; ++i) {
            const int k = int((i + step) % 4);
            if (m.neighbors[size_t(t) * 4 + k] != kNoTet && outside(m, t, k, p) > 0) {
                next = k;
                break;
            }
        }
        if (next < 0) return t;
        t = m.neighbors[size_t(t) * 4 + next];
    }
    uint32_t best = 0;
    double best_out = INFINITY;
    for (uint32_t c = 0; c < tets; ++c) {
        double worst = -INFINITY;
        for (int k = 0; k < 4; ++k) {
            Vec3d n, a;
            face_plane(m, c, k, n, a);
            const double len = std::sqrt(dot(n, n));
            worst = std::max(worst, len > 0 ? dot(n, p - a) / len : 0.0);
        }
        if (worst < best_out) {
            best_out = worst;
            best = c;
        }
    }
    return best;
}

}  // namespace thicket::tetra_detail
