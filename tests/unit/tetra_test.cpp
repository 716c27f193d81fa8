// The tetrahedralization: a clean closed mesh is meshed whole; what TetGen refuses
// (intersecting triangles, degenerate ones, too many) goes to the fallback and is still hit;
// the walk agrees with brute force; a corrupted payload is refused.
#include <gtest/gtest.h>

#include <sstream>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"
#include "thicket/tetra/tetra.h"

namespace thicket::tetra_test {
namespace {

const Scene& scene_named(const std::string& name) {
    static const std::vector<Scene> scenes = testing::nasty_scenes();
    for (const Scene& s : scenes)
        if (s.name == name) return s;
    throw Error("no nasty scene " + name);
}

void add_triangle(TriangleMesh& m, Vec3 a, Vec3 b, Vec3 c) {
    const auto base = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

std::string extra(const AccelStats& s, const std::string& key) {
    for (const auto& [k, v] : s.extra)
        if (k == key) return v;
    return "";
}

/// Whether `accel` answers every conformance ray of `scene` like brute force (same primitive
/// and t, or a miss for both).
void expect_like_brute(const Accel& accel, const Scene& scene) {
    const auto brute = build_accel("brute", scene);
    for (const Ray& r : testing::conformance_rays(scene, 1500)) {
        const Hit a = accel.intersect(r), b = brute->intersect(r);
        ASSERT_EQ(a.found(), b.found());
        if (a.found()) {
            ASSERT_NEAR(a.t, b.t, 1e-5f * std::fabs(b.t));
        }
        ASSERT_EQ(accel.occluded(r), brute->occluded(r));
    }
}

TEST(Tetra, ClosedCubeIsMeshedWhole) {
    const Scene& scene = scene_named("closed-cube");
    const auto accel = build_accel("tetra", scene);
    const AccelStats s = accel->stats();
    EXPECT_EQ(extra(s, "fallback primitives"), "0 (in a bvh)");
    EXPECT_EQ(extra(s, kLimitedKey), "");
    EXPECT_GT(std::stoul(extra(s, "tetrahedra")), scene.primitive_count() / 2);
    expect_like_brute(*accel, scene);
}

TEST(Tetra, IntersectingTrianglesGoToTheFallbackAndAreStillHit) {
    // Two triangles piercing each other (TetGen 1.5 crashes on these: the child process
    // absorbs it) and one apart from them, which stays meshed.
    Scene scene;
    scene.name = "pierced";
    add_triangle(scene.mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0});
    add_triangle(scene.mesh, {0.2f, 0.2f, -0.5f}, {0.3f, 0.2f, 0.5f}, {0.2f, 0.8f, 0.5f});
    add_triangle(scene.mesh, {-1, -1, 1}, {-0.5f, -1, 1}, {-1, -0.5f, 1.2f});
    const auto accel = build_accel("tetra", scene);
    const AccelStats s = accel->stats();
    EXPECT_EQ(extra(s, "triangles meshed"), "1 of 3 triangles");
    EXPECT_NE(extra(s, kLimitedKey).find("intersecting"), std::string::npos) << extra(s, kLimitedKey);
    // Straight down through the second triangle, which only the fallback holds.
    const Hit h = accel->intersect(Ray{{0.25f, 0.5f, 2}, 0.0f, {0, 0, -1}, kInfinity});
    EXPECT_TRUE(h.found());
    expect_like_brute(*accel, scene);
}

TEST(Tetra, ScenesOverTheLimitAreNotHandedToTetGen) {
    const Scene& scene = scene_named("soup");
    const auto accel = build_accel("tetra:max-triangles=100", scene);
    const AccelStats s = accel->stats();
    EXPECT_EQ(extra(s, "tetrahedra"), "0");
    EXPECT_EQ(extra(s, "TetGen"), "0.0 ms in 0 run(s)");
    EXPECT_NE(extra(s, kLimitedKey).find("over max-triangles=100"), std::string::npos);
    expect_like_brute(*accel, scene);
}

TEST(Tetra, PreservedSurfaceAddsNoSteinerPointOnTriangles) {
    const Scene& scene = scene_named("closed-cube");
    TetraBuildOptions o;
    o.preserve_surface = true;
    const Tetra<Triangles<>> tetra(Triangles<>(scene.mesh), o);
    // Every triangle is one constrained face: listed at its three vertices and nowhere else.
    EXPECT_EQ(tetra.data().mesh.vertex_tris.size(), 3 * scene.primitive_count());
    EXPECT_TRUE(tetra.data().fallback.empty());
    expect_like_brute(tetra, scene);
}

TEST(Tetra, CorruptedPayloadIsRefused) {
    const Scene& scene = scene_named("closed-cube");
    const Tetra<Triangles<>> tetra(Triangles<>(scene.mesh), TetraBuildOptions{});
    TetraData bad = tetra.data();
    ASSERT_GT(bad.mesh.tets.size(), 5u) << "the closed cube was not meshed";
    bad.mesh.tets[5] = uint32_t(bad.mesh.points.size());
    EXPECT_THROW(validate_tetra(bad, scene.primitive_count()), Error);
    bad = tetra.data();
    bad.mesh.vertex_tris.clear();  // no triangle meshed, none in the fallback either
    bad.mesh.vertex_offsets.assign(bad.mesh.vertex_offsets.size(), 0);
    EXPECT_THROW(validate_tetra(bad, scene.primitive_count()), Error);
    std::stringstream bytes;
    write_tetra(bytes, tetra.data());
    const std::string text = bytes.str();
    std::stringstream cut(text.substr(0, text.size() / 2));
    EXPECT_THROW(read_tetra(cut, scene.primitive_count()), Error);
    std::stringstream whole(text);
    const TetraData back = read_tetra(whole, scene.primitive_count());
    EXPECT_EQ(back.mesh.tets, tetra.data().mesh.tets);
}

}  // namespace
}  // namespace thicket::tetra_test
