#pragma once
/// The walk of a ray through the tetrahedral mesh (Lagae & Dutré 2008): start in the tetrahedron
/// holding the ray's first point inside the box (point location), leave each tetrahedron
/// through the face whose plane the ray crosses first going out, until past the closest hit.
/// The triangle a crossed face is part of is tested. Where rounding could make the walk and the
/// triangle test disagree — in the first tetrahedron (located, not entered), and wherever the
/// ray leaves a tetrahedron within kNearEdge (barycentric) of an edge or vertex of the exit face
/// — every scene triangle at the tetrahedron's four vertices is tested as well: a triangle the
/// ray hits there has a constrained face at one of those vertices. Each triangle is tested once
/// per ray (mailbox).
///
/// A recording policy (core/traversal_record.h) is told each tetrahedron the walk enters, in
/// order, with the distance at which the ray enters it (the first: where the ray enters the box),
/// and each triangle tested; the point-location steps before the walk are counted, not listed:
/// they do not lie along the ray.
#include <algorithm>
#include <cmath>

#include "thicket/core/mailbox.h"
#include "thicket/core/ray.h"
#include "thicket/core/traversal_record.h"
#include "thicket/tetra/walk.h"

namespace thicket::tetra_detail {

/// Steps a walk may take without the ray's distance growing before it is given up (a ray
/// through a vertex where rounding leaves it circling); then every triangle is tested.
inline constexpr uint32_t kStallSteps = 4096;

/// Entry and exit distance of the ray in the mesh's box, in double; false when it misses.
inline bool box_span(const TetraMesh& m, const Vec3d& o, const Vec3d& d, double& t0, double& t1) {
    for (int a = 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < m.box_min[a] || o[a] > m.box_max[a]) return false;
            continue;
        }
        double n = (m.box_min[a] - o[a]) / d[a], f = (m.box_max[a] - o[a]) / d[a];
        if (n > f) std::swap(n, f);
        t0 = std::max(t0, n);
        t1 = std::min(t1, f);
    }
    return t0 <= t1;
}

/// How close (in barycentric coordinates of the exit face) the ray may pass to an edge or
/// vertex before the triangles around the tetrahedron's vertices are tested too.
inline constexpr double kNearEdge = 1e-3;

/// Walks `ray` through the mesh: closest hit (AnyHit false: narrows `hit`, whose t is the far
/// end of the search) or any hit (returns true at the first). `test(prim)` runs the primitive
/// test and returns whether it hit; `test_all(mailbox)` tests every meshed triangle (a stalled
/// walk) and returns whether anything was hit (any-hit).
template <bool AnyHit, class C, class Test, class TestAll>
bool walk(const TetraMesh& m, size_t primitives, const Ray& ray, const Hit& hit, C& counters, Test&& test,
          TestAll&& test_all) {
    if (m.tet_count() == 0) return false;
    const Vec3d o{ray.org.x, ray.org.y, ray.org.z}, d{ray.dir.x, ray.dir.y, ray.dir.z};
    double t_in = ray.tmin, t_box_out = ray.tmax;
    if (!box_span(m, o, d, t_in, t_box_out)) return false;
    // The first point inside the box, clamped into it against rounding.
    Vec3d p = o + d * t_in;
    p = {std::clamp(p.x, m.box_min.x, m.box_max.x), std::clamp(p.y, m.box_min.y, m.box_max.y),
         std::clamp(p.z, m.box_min.z, m.box_max.z)};
    uint32_t t = locate(m, p, grid_start(m, p), [&] { counters.node(); });
    Mailbox mailbox(primitives);
    auto offer = [&](uint32_t prim) {
        if (prim == kNoTet || !mailbox.first_visit(prim)) return false;
        counters.prim();
        const bool found = test(prim);
        if constexpr (RecordsSteps<C>) counters.record_prim(prim, AnyHit ? ray.tmax : hit.t);
        return found;
    };
    auto around = [&](uint32_t tet) {
        const uint32_t* v = &m.tets[size_t(tet) * 4];
        for (int i = 0; i < 4; ++i)
            for (uint32_t j = m.vertex_offsets[v[i]]; j < m.vertex_offsets[v[i] + 1]; ++j)
                if (offer(m.vertex_tris[j]) && AnyHit) return true;
        return false;
    };
    int entry = -1;
    uint32_t stalled = 0;
    bool first = true;
    while (true) {
        counters.node();
        if constexpr (RecordsSteps<C>) counters.record_node(t, float(t_in));
        if (first) {
            first = false;
            if (around(t)) return true;
        }
        // The exit: the face the ray leaves through first (its plane crossed going outward).
        int exit = -1;
        double t_exit = INFINITY, num[4], nd[4], height[4];
        for (int k = 0; k < 4; ++k) {
            Vec3d n, a;
            face_plane(m, t, k, n, a);
            num[k] = dot(n, a - o);
            nd[k] = dot(n, d);
            height[k] = dot(n, a - m.points[m.tets[size_t(t) * 4 + k]]);
            if (k == entry || !(nd[k] > 0)) continue;
            const double tk = num[k] / nd[k];
            if (tk < t_exit) {
                t_exit = tk;
                exit = k;
            }
        }
        if (exit < 0) return false;  // a closed box: only where the ray ends
        t_exit = std::max(t_exit, t_in);
        if (offer(m.face_tris[size_t(t) * 4 + exit]) && AnyHit) return true;
        // Near an edge or vertex of the exit face: its other barycentric coordinates are small.
        bool near = false;
        for (int k = 0; k < 4; ++k)
            if (k != exit) near = near || !((num[k] - t_exit * nd[k]) > kNearEdge * height[k]);
        if (near && around(t)) return true;
        const double far = AnyHit ? ray.tmax : hit.t;
        if (!(t_exit <= far + 1e-4 * std::fabs(far)) || t_exit > t_box_out) return false;
        const uint32_t next = m.neighbors[size_t(t) * 4 + exit];
        if (next == kNoTet) return false;
        stalled = t_exit > t_in ? 0 : stalled + 1;
        if (stalled > kStallSteps) return test_all(mailbox);
        entry = -1;
        for (int k = 0; k < 4; ++k)
            if (m.neighbors[size_t(next) * 4 + k] == t) entry = k;
        t = next;
        t_in = t_exit;
    }
}

}  // namespace thicket::tetra_detail
