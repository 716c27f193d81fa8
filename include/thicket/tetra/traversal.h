#pragma once
/// The walk of a ray through the tetrahedral mesh (Lagae & Dutré 2008): start in the tetrahedron
/// holding the ray's first point inside the box (point location), leave each tetrahedron
/// through the face whose plane the ray crosses first going out, until past the closest hit.
/// In each tetrahedron the scene triangles at its four vertices are tested: a triangle the ray
/// hits inside the tetrahedron has a constrained face there, whose vertices are the
/// tetrahedron's; and a walk that rounding moves onto the neighbouring tetrahedron across an
/// edge or vertex still shares that edge's or vertex's triangles. Each triangle is tested once
/// per ray (mailbox).
#include <algorithm>
#include <cmath>

#include "thicket/core/mailbox.h"
#include "thicket/core/ray.h"
#include "thicket/tetra/walk.h"

namespace thicket::tetra_detail {

/// Steps a walk may take without the ray's distance growing before it is given up (a ray
/// through a vertex where rounding leaves it circling); then every triangle is tested.
inline constexpr uint32_t kStallSteps = 4096;

/// Entry and exit distance of the ray in the mesh's box, in double; false when it misses.
inline bool box_span(const TetraMesh& m, const D3& o, const D3& d, double& t0, double& t1) {
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

/// Walks `ray` through the mesh: closest hit (AnyHit false: narrows `hit`, whose t is the far
/// end of the search) or any hit (returns true at the first). `test(prim)` runs the primitive
/// test and returns whether it hit; `all(…)` tests every meshed triangle (a stalled walk).
template <bool AnyHit, class C, class Test, class TestAll>
bool walk(const TetraMesh& m, size_t primitives, const Ray& ray, const Hit& hit, C& counters, Test&& test,
          TestAll&& test_all) {
    if (m.tet_count() == 0) return false;
    const D3 o{ray.org.x, ray.org.y, ray.org.z}, d{ray.dir.x, ray.dir.y, ray.dir.z};
    double t_in = ray.tmin, t_box_out = ray.tmax;
    if (!box_span(m, o, d, t_in, t_box_out)) return false;
    // The first point inside the box, clamped into it against rounding.
    D3 p = o + d * t_in;
    p = {std::clamp(p.x, m.box_min.x, m.box_max.x), std::clamp(p.y, m.box_min.y, m.box_max.y),
         std::clamp(p.z, m.box_min.z, m.box_max.z)};
    uint32_t t = locate(m, p, grid_start(m, p), [&] { counters.node(); });
    Mailbox mailbox(primitives);
    int entry = -1;
    uint32_t stalled = 0;
    while (true) {
        counters.node();
        const uint32_t* v = &m.tets[size_t(t) * 4];
        for (int i = 0; i < 4; ++i)
            for (uint32_t j = m.vertex_offsets[v[i]]; j < m.vertex_offsets[v[i] + 1]; ++j) {
                const uint32_t prim = m.vertex_tris[j];
                if (!mailbox.first_visit(prim)) continue;
                counters.prim();
                if (test(prim) && AnyHit) return true;
            }
        // The exit: the face the ray leaves through first (its plane crossed going outward).
        int exit = -1;
        double t_exit = INFINITY;
        for (int k = 0; k < 4; ++k) {
            if (k == entry) continue;
            D3 n, a;
            face_plane(m, t, k, n, a);
            const double nd = dot(n, d);
            if (!(nd > 0)) continue;
            const double tk = dot(n, a - o) / nd;
            if (tk < t_exit) {
                t_exit = tk;
                exit = k;
            }
        }
        if (exit < 0) return false;  // a closed box: only where the ray ends
        t_exit = std::max(t_exit, t_in);
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
