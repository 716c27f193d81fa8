// The tetrahedral walk as recorded (tetra/traversal.h with a TraversalRecorder): the tetrahedra
// a ray enters come in order, each sharing a face (three vertices) with the one before, at
// non-decreasing entry distances, and the ray's segment inside the last one holds the hit; the
// steps and totals agree with the plain counting path, for closest and any hit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"
#include "thicket/tetra/tetra.h"

namespace thicket {
namespace tetra_walk_record_test {

const Scene& scene_named(const std::string& name) {
    static const std::vector<Scene> scenes = testing::nasty_scenes();
    for (const Scene& s : scenes)
        if (s.name == name) return s;
    throw Error("no nasty scene " + name);
}

/// The mesh of a `tetra` built over a triangle scene (the registry's default triangle test).
const TetraMesh& mesh_of(const Accel& accel) {
    const auto* t = dynamic_cast<const Tetra<Triangles<TriangleTest::Moller>>*>(&accel);
    if (!t) throw Error("not a tetra over Moller triangles: " + accel.spec());
    return t->data().mesh;
}

/// The vertex ids tetrahedra a and b share.
size_t shared_vertices(const TetraMesh& m, uint32_t a, uint32_t b) {
    size_t n = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) n += m.tets[size_t(a) * 4 + i] == m.tets[size_t(b) * 4 + j];
    return n;
}

/// The ray's parameter interval inside tetrahedron t, clipped by its four face planes in double,
/// each face's inside told by the vertex opposite it (independent of the walk's face_plane).
void segment_in(const TetraMesh& m, uint32_t t, const Ray& ray, double& lo, double& hi) {
    const Vec3d o{ray.org.x, ray.org.y, ray.org.z}, d{ray.dir.x, ray.dir.y, ray.dir.z};
    lo = -INFINITY;
    hi = INFINITY;
    for (int k = 0; k < 4; ++k) {
        Vec3d f[3];
        for (int i = 0, j = 0; i < 4; ++i)
            if (i != k) f[j++] = m.points[m.tets[size_t(t) * 4 + i]];
        Vec3d n = cross(f[1] - f[0], f[2] - f[0]);
        if (dot(n, m.points[m.tets[size_t(t) * 4 + k]] - f[0]) > 0) n = n * -1.0;  // outward
        const double num = dot(n, f[0] - o), den = dot(n, d);
        if (den > 0)
            hi = std::min(hi, num / den);
        else if (den < 0)
            lo = std::max(lo, num / den);
    }
}

struct Walked {
    std::vector<uint32_t> tets;
    std::vector<float> t_enter;
    std::vector<uint32_t> prims;
};

Walked walked(const TraversalRecorder& rec) {
    Walked w;
    for (const TraversalStep& s : rec.steps) {
        EXPECT_NE(s.kind, TraversalStep::Kind::Cull);  // a walk culls nothing
        EXPECT_NE(s.kind, TraversalStep::Kind::Skip);
        if (s.kind == TraversalStep::Kind::Enter) {
            w.tets.push_back(s.id);
            w.t_enter.push_back(s.t);
        } else {
            w.prims.push_back(s.id);
        }
    }
    return w;
}

/// Checks one recorded walk: face-adjacent tetrahedra in order of entry; returns nothing, fails the test.
void expect_face_adjacent(const TetraMesh& m, const Walked& w, size_t prims) {
    for (size_t i = 0; i < w.tets.size(); ++i) {
        ASSERT_LT(w.tets[i], m.tet_count());
        if (i == 0) continue;
        ASSERT_EQ(shared_vertices(m, w.tets[i - 1], w.tets[i]), 3u)
            << "tetrahedra " << w.tets[i - 1] << " and " << w.tets[i] << " (steps " << i - 1 << ", " << i << ")";
        ASSERT_GE(w.t_enter[i], w.t_enter[i - 1]);
    }
    for (uint32_t p : w.prims) ASSERT_LT(p, prims);
    // Each triangle is tested once per ray (the mailbox).
    EXPECT_EQ(std::set<uint32_t>(w.prims.begin(), w.prims.end()).size(), w.prims.size());
}

void check_scene(const std::string& name, size_t* walks_ending_at_a_hit) {
    const Scene& scene = scene_named(name);
    const auto accel = build_accel("tetra", scene);
    const TetraMesh& m = mesh_of(*accel);
    ASSERT_GT(m.tet_count(), 0u);
    for (const Ray& ray : testing::conformance_rays(scene, 400)) {
        TraversalRecorder rec;
        const Hit hit = accel->intersect(ray, rec);
        ASSERT_TRUE(rec.detailed);
        ASSERT_EQ(rec.dropped, 0u);
        RayCounters plain;
        const Hit expected = accel->intersect(ray, plain);
        ASSERT_EQ(hit.prim, expected.prim);
        ASSERT_EQ(rec.nodes, plain.nodes);
        ASSERT_EQ(rec.prims, plain.prims);
        const Walked w = walked(rec);
        ASSERT_EQ(w.prims.size(), rec.prims);  // every primitive test is listed
        expect_face_adjacent(m, w, scene.primitive_count());
        if (hit.found()) {
            // The walk went on until past the hit: the hit triangle was tested, with that
            // answer, and the ray's stretch inside the last tetrahedron holds the hit point.
            ASSERT_FALSE(w.tets.empty());
            ASSERT_NE(std::find(w.prims.begin(), w.prims.end(), hit.prim), w.prims.end());
            const auto last_test = std::find_if(rec.steps.rbegin(), rec.steps.rend(), [](const TraversalStep& s) {
                return s.kind == TraversalStep::Kind::Prim;
            });
            ASSERT_EQ(last_test->t, hit.t);
            double lo = 0, hi = 0;
            segment_in(m, w.tets.back(), ray, lo, hi);
            const double slack = 1e-4 * std::fabs(hit.t) + 1e-6;
            EXPECT_LE(lo, hit.t + slack) << name << ": last tetrahedron " << w.tets.back() << " begins at " << lo
                                         << ", past the hit at " << hit.t;
            EXPECT_GE(hi, hit.t - slack) << name << ": last tetrahedron " << w.tets.back() << " ends at " << hi
                                         << ", before the hit at " << hit.t;
            ++*walks_ending_at_a_hit;
        }
        // The shadow query walks the same way, and stops at the first hit.
        TraversalRecorder any_rec;
        RayCounters any_plain;
        const auto& tetra = dynamic_cast<const Tetra<Triangles<TriangleTest::Moller>>&>(*accel);
        ASSERT_EQ(tetra.any(ray, any_rec), accel->occluded(ray, any_plain));
        ASSERT_EQ(any_rec.nodes, any_plain.nodes);
        expect_face_adjacent(m, walked(any_rec), scene.primitive_count());
    }
}

}  // namespace tetra_walk_record_test

using namespace tetra_walk_record_test;

TEST(TetraWalkRecord, ClosedCubeWalksFaceAdjacentTetrahedraToTheHit) {
    size_t hits = 0;
    check_scene("closed-cube", &hits);
    EXPECT_GT(hits, 50u);  // the check above ran on real walks, not only on misses
}

TEST(TetraWalkRecord, SoupWithFallbackListsTetrahedraAndSceneIdsOnly) {
    // Intersecting triangles: some go to the fallback BVH, whose node ids must not be listed as
    // tetrahedra; its primitives are listed under their scene ids.
    size_t hits = 0;
    check_scene("soup", &hits);
    EXPECT_GT(hits, 50u);
}

TEST(TetraWalkRecord, ThinSticksWalkFaceAdjacentTetrahedra) {
    size_t hits = 0;
    check_scene("thin-diagonal", &hits);
    EXPECT_GT(hits, 10u);
}

}  // namespace thicket
