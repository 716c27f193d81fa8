// A scene's geometries (Scene::geometries): each add_* call is one geometry, numbered in call
// order, and geometry_of() maps the primitive id a structure answers back to it — the seam that
// instancing, refit and the front ends' geometry ids build on.
#include <gtest/gtest.h>

#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/scene/scene.h"
#include "support/temp_dir.h"

namespace scene_geometries_test {

using namespace thicket;

namespace {

/// `count` triangles in the plane z = `z`, side by side along x.
TriangleMesh strip(int count, float z) {
    TriangleMesh m;
    for (int i = 0; i < count; ++i) {
        const auto base = uint32_t(m.positions.size());
        const float x = float(i);
        m.positions.insert(m.positions.end(), {{x, 0, z}, {x + 1, 0, z}, {x, 1, z}});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    return m;
}

}  // namespace

TEST(SceneGeometries, EachAddCallIsOneGeometryInCallOrder) {
    Scene s;
    EXPECT_EQ(s.geometry_count(), 0u);
    EXPECT_EQ(s.add_mesh(strip(2, 0)), 0u);              // ids 0, 1
    EXPECT_EQ(s.add_shape(Sphere{{0, 0, 5}, 1}), 1u);     // id 2
    EXPECT_EQ(s.add_mesh(TriangleMesh{}), 2u);            // empty: no id
    const std::vector<Shape> set = {Sphere{{3, 0, 5}, 1}, Sphere{{6, 0, 5}, 1}, Sphere{{9, 0, 5}, 1}};
    EXPECT_EQ(s.add_shapes(set), 3u);                     // ids 3, 4, 5
    EXPECT_EQ(s.add_mesh(strip(3, 1)), 4u);               // ids 6, 7, 8
    ASSERT_EQ(s.primitive_count(), 9u);
    ASSERT_EQ(s.geometry_count(), 5u);

    const uint32_t expected[9] = {0, 0, 1, 3, 3, 3, 4, 4, 4};
    for (uint32_t prim = 0; prim < 9; ++prim) EXPECT_EQ(s.geometry_of(prim), expected[prim]) << "prim " << prim;
    EXPECT_EQ(s.geometry_of(9), kNoPrim);
    EXPECT_EQ(s.geometry_of(kNoPrim), kNoPrim);  // a miss stays a miss
    EXPECT_EQ(s.geometry(2).count, 0u);
    EXPECT_EQ(s.geometry(3).first, 3u);
    EXPECT_EQ(s.geometry(3).count, 3u);
    // The geometries' ids still name what they added: triangles 2..4 are the second mesh's.
    EXPECT_FALSE(s.locate(6).shape);
    EXPECT_EQ(s.locate(6).index, 2u);
    EXPECT_TRUE(s.locate(4).shape);
}

TEST(SceneGeometries, AnAssignedSceneIsOneGeometryUntilSomethingIsAdded) {
    Scene s;
    s.mesh = strip(4, 0);
    EXPECT_EQ(s.geometry_count(), 1u);
    EXPECT_EQ(s.geometry_of(3), 0u);
    EXPECT_EQ(s.geometry(0).count, 4u);
    EXPECT_EQ(s.add_shape(Sphere{{0, 0, 5}, 1}), 1u);  // what was there became geometry 0
    EXPECT_EQ(s.geometry_of(3), 0u);
    EXPECT_EQ(s.geometry_of(4), 1u);
}

TEST(SceneGeometries, LoadersMakeOneGeometryPerSceneEntry) {
    // A mesh file is one geometry; the built-in teapot's 32 patches are one set.
    EXPECT_EQ(load_scene("cornell").geometry_count(), 1u);
    const Scene teapot = load_scene("teapot-patches");
    EXPECT_EQ(teapot.geometry_count(), 1u);
    EXPECT_EQ(teapot.geometry_of(31), 0u);

    // A JSON scene: each shape entry is a geometry, in file order.
    const thicket::testing::TempDir dir("scene_geometries");
    const std::string path = dir.file("three.json", R"({"shapes": [
        {"type": "sphere", "center": [0, 0, 0], "radius": 1},
        {"type": "sphere", "center": [4, 0, 0], "radius": 1},
        {"type": "torus", "center": [8, 0, 0], "major_radius": 1, "minor_radius": 0.25}]})");
    const Scene json = load_scene(path);
    ASSERT_EQ(json.primitive_count(), 3u);
    EXPECT_EQ(json.geometry_count(), 3u);
    EXPECT_EQ(json.geometry_of(2), 2u);
}

TEST(SceneGeometries, AHitsPrimitiveNamesTheGeometryItIsOn) {
    // Two strips at z = 0 and z = 1, added separately; rays from above hit the upper one's
    // triangles and the geometry id says so, under a structure that only knows primitive ids.
    Scene s;
    s.add_mesh(strip(3, 0));
    s.add_mesh(strip(3, 1));
    const auto bvh = build_accel("bvh", s, 1);
    for (int i = 0; i < 3; ++i) {
        const Hit from_above = bvh->intersect(Ray{{float(i) + 0.25f, 0.25f, 5}, 0, {0, 0, -1}});
        ASSERT_TRUE(from_above.found());
        EXPECT_EQ(s.geometry_of(from_above.prim), 1u);
        const Hit from_below = bvh->intersect(Ray{{float(i) + 0.25f, 0.25f, -5}, 0, {0, 0, 1}});
        ASSERT_TRUE(from_below.found());
        EXPECT_EQ(s.geometry_of(from_below.prim), 0u);
    }
}

}  // namespace scene_geometries_test
