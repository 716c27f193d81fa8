// bvh8's closest-point query under every ISA this CPU runs, against brute force bitwise: the
// leaves use brute force's point-triangle test and ties go to the lower id, so the point, the
// distance and the primitive must all be brute force's, also where several triangles are equally
// close (points on shared vertices and edges) and for degenerate triangles, which the ray
// kernels never see but which are still closest points.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>

#include "thicket/accel/registry.h"
#include "thicket/bvh8/isa.h"
#include "thicket/core/error.h"

namespace thicket::bvh8_closest_point_test {
namespace {

/// A grid of quads on the plane z = 0 (every interior vertex shared by 6 triangles), a few
/// needles and collinear triangles above it, and a triangle whose three vertices coincide.
Scene grid_with_slivers() {
    TriangleMesh mesh;
    constexpr int kN = 12;
    for (int y = 0; y <= kN; ++y)
        for (int x = 0; x <= kN; ++x) mesh.positions.push_back({float(x), float(y), 0.0f});
    for (int y = 0; y < kN; ++y)
        for (int x = 0; x < kN; ++x) {
            const uint32_t a = uint32_t(y * (kN + 1) + x), b = a + 1, c = a + kN + 1, d = c + 1;
            for (uint32_t i : {a, b, d, a, d, c}) mesh.indices.push_back(i);
        }
    auto add = [&](Vec3 p, Vec3 q, Vec3 r) {
        const auto first = uint32_t(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {p, q, r});
        for (uint32_t k = 0; k < 3; ++k) mesh.indices.push_back(first + k);
    };
    add({2, 2, 3}, {5, 5, 3}, {8, 8, 3});      // collinear: degenerate
    add({1, 9, 2}, {4, 9, 2}, {4, 9, 2});      // two vertices equal: degenerate
    add({6, 6, 1.5f}, {6, 6, 1.5f}, {6, 6, 1.5f});  // a point
    add({9, 1, 4}, {11, 1, 4}, {10, 1e-8f, 4});  // a needle close to degenerate
    Scene scene;
    scene.name = "grid-with-slivers";
    scene.add_mesh(mesh);
    return scene;
}

/// Random points around the scene, and points exactly on grid vertices, edges and on the slivers.
std::vector<Vec3> query_points(const Scene& scene) {
    std::mt19937 rng(4);
    const Aabb b = scene.bounds();
    std::uniform_real_distribution<float> u(-0.3f, 1.3f);
    std::vector<Vec3> points;
    for (int i = 0; i < 400; ++i) {
        const Vec3 e = b.extent();
        points.push_back(b.min + Vec3{e.x * u(rng), e.y * u(rng), e.z * u(rng)});
    }
    for (int i = 0; i < 100; ++i) points.push_back({float(i % 13), float(i / 13 % 13), (i % 3) * 0.5f});
    for (int i = 0; i < 100; ++i) points.push_back({float(i % 12) + 0.5f, float(i / 12 % 12), 0.0f});
    points.insert(points.end(), {{5, 5, 3}, {5, 5, 3.5f}, {3, 9, 2}, {6, 6, 1.5f}, {6, 6, 2}, {10, 0.5f, 4}});
    return points;
}

void expect_same_as_brute(const Scene& scene, const std::vector<Vec3>& points, const std::string& isect) {
    const std::unique_ptr<Accel> brute = build_accel("brute:isect=" + isect, scene);
    std::vector<NearestPoint> want(points.size());
    brute->closest_points(points, want);
    for (Isa isa : cpu_isas()) {
        const std::string spec = std::string("bvh8:isa=") + isa_name(isa) + ",isect=" + isect;
        SCOPED_TRACE(spec);
        const std::unique_ptr<Accel> accel = build_accel(spec, scene);
        ASSERT_TRUE(accel->has_closest_point());
        std::vector<NearestPoint> got(points.size());
        BatchOptions two;
        two.threads = 2;
        accel->closest_points(points, got, two);
        size_t wrong = 0;
        for (size_t i = 0; i < points.size(); ++i) {
            const bool same = got[i].prim == want[i].prim && got[i].distance == want[i].distance &&
                              got[i].point == want[i].point && got[i].u == want[i].u && got[i].v == want[i].v;
            if (!same && wrong++ < 3)
                ADD_FAILURE() << "point " << i << " (" << points[i].x << ", " << points[i].y << ", " << points[i].z
                              << "): prim " << got[i].prim << " at " << got[i].distance << ", brute force prim "
                              << want[i].prim << " at " << want[i].distance;
        }
        EXPECT_EQ(wrong, 0u);
    }
}

TEST(Bvh8ClosestPoint, EveryIsaAnswersBitwiseLikeBruteForceTiesAndSliversIncluded) {
    const Scene scene = grid_with_slivers();
    const std::vector<Vec3> points = query_points(scene);
    expect_same_as_brute(scene, points, "moller");
    expect_same_as_brute(scene, points, "watertight");
}

TEST(Bvh8ClosestPoint, CornellBoxAgreesWithBruteForce) {
    const Scene scene = load_scene("cornell");
    expect_same_as_brute(scene, query_points(scene), "moller");
}

TEST(Bvh8ClosestPoint, AllDegenerateSceneIsAnsweredFromTheSliverTree) {
    TriangleMesh mesh;
    for (int i = 0; i < 20; ++i) {
        const float x = float(i);
        mesh.positions.insert(mesh.positions.end(), {{x, 0, 0}, {x + 0.5f, 0, 0}, {x + 1, 0, 0}});
        for (uint32_t k = 0; k < 3; ++k) mesh.indices.push_back(uint32_t(3 * i) + k);
    }
    Scene scene;
    scene.name = "collinear-only";
    scene.add_mesh(mesh);
    const std::unique_ptr<Accel> accel = build_accel("bvh8", scene);
    EXPECT_FALSE(accel->intersect(Ray{{3.3f, 0, 1}, 0.0f, {0, 0, -1}, kInfinity}).found()) << "never hit by rays";
    const NearestPoint p = accel->closest_point({3.3f, 0, 1});
    ASSERT_TRUE(p.found());
    EXPECT_FLOAT_EQ(p.distance, 1.0f);
    expect_same_as_brute(scene, {{3.3f, 0, 1}, {-2, 0, 0}, {25, 1, 1}, {7, 0, 0}}, "moller");
}

TEST(Bvh8ClosestPoint, EmptySceneFindsNothingAndShapesAreRefused) {
    Scene empty;
    empty.name = "empty";
    const std::unique_ptr<Accel> none = build_accel("bvh8", empty);
    EXPECT_FALSE(none->closest_point({0, 0, 0}).found());
    const std::unique_ptr<Accel> shapes = build_accel("bvh8", load_scene("teapot-patches"));
    EXPECT_FALSE(shapes->has_closest_point());
    EXPECT_THROW(shapes->closest_point({0, 0, 0}), Error);
}

}  // namespace
}  // namespace thicket::bvh8_closest_point_test
