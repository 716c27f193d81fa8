// load_scene tests: dispatch by extension and its errors, the built-in Cornell box, the
// fingerprint, and the shared real scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "loader_test_util.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::loader_scene_test {
namespace {

using namespace loader_test;

// ---- load_scene --------------------------------------------------------------------------------

TEST(LoaderScene, DispatchAndErrors) {
    TempDir tmp;
    const Scene s = load_scene(tmp.file("Mesh.PLY", simple_ply(Fmt::le)));
    EXPECT_EQ(s.name, tmp.dir() + "/Mesh.PLY");
    expect_reference(s.mesh);
    const std::string unknown = tmp.file("mesh.stl", "solid");
    expect_error([&] { load_scene(unknown); }, unknown, {".ply", ".obj", ".gltf", ".glb", "cornell"});
    const std::string none = tmp.file("mesh", "ply");
    expect_error([&] { load_scene(none); }, none, {"cornell"});
    expect_error([&] { load_scene(tmp.dir()); }, tmp.dir(), {"directory"});
    expect_error([&] { load_scene(tmp.dir() + "/nope.ply"); }, tmp.dir() + "/nope.ply", {"no such file"});
    EXPECT_STREQ(builtin_scene_names(), "cornell, teapot-patches");
    expect_error([&] { load_scene(none); }, none, {"teapot-patches"});
}

TEST(LoaderScene, CornellBuiltin) {
    const Scene s = load_scene("cornell");
    EXPECT_EQ(s.name, "cornell");
    EXPECT_EQ(s.primitive_count(), 36u);
    EXPECT_EQ(s.mesh.positions.size(), 72u);
    EXPECT_EQ(s.bounds().min, Vec3(-1.02f, 0.0f, -1.04f));
    EXPECT_EQ(s.bounds().max, Vec3(1.0f, 1.99f, 0.99f));
    ASSERT_EQ(s.mesh.material_ids.size(), 36u);
    const Material& light = s.mesh.materials[s.mesh.material_ids[35]];
    EXPECT_EQ(light.name, "light");
    EXPECT_GT(light.emission.x, 1.0f);
    EXPECT_EQ(s.mesh.materials[s.mesh.material_ids[0]].name, "floor");
    for (uint32_t t = 0; t < 36; ++t) EXPECT_GT(length(s.geometric_normal(t)), 0.0f) << t;
}

TEST(LoaderScene, FingerprintIsFnv1aOverVertexBits) {
    Scene s;
    s.mesh.positions = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
    s.mesh.indices = {0, 1, 2};
    uint64_t h = 0xcbf29ce484222325ull;
    auto bytes = [&](const void* p, size_t n) {
        for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const unsigned char*>(p)[i]) * 0x100000001b3ull;
    };
    for (const Vec3& v : s.mesh.positions) bytes(&v, 12);
    const uint64_t count = 1;
    bytes(&count, 8);
    EXPECT_EQ(s.fingerprint(), h);
    const uint64_t before = s.fingerprint();
    s.mesh.positions[2].z = 9.0000010f;
    EXPECT_NE(s.fingerprint(), before);
    EXPECT_EQ(load_scene("cornell").fingerprint(), load_scene("cornell").fingerprint());
}

// ---- shared real scenes ------------------------------------------------------------------------

bool shared_scenes_present() {
    std::error_code ec;
    return fs::is_directory(THICKET_SHARED_SCENES, ec);
}

TEST(LoaderShared, PlyCountsAndBoundsMatchReadme) {
    if (!shared_scenes_present()) GTEST_SKIP() << "../shared/scenes not found: " << THICKET_SHARED_SCENES;
    struct Row {
        const char* file;
        size_t tris, verts;
        Vec3 lo, hi;
    };
    const Row rows[] = {
        {"cornell-box.ply", 36, 72, {-1.02f, 0, -1.04f}, {1, 1.99f, 0.99f}},
        {"teapot.ply", 6320, 3644, {-3, 0, -2}, {3.434f, 3.15f, 2}},
        {"sponza-dabrovic.ply",
         66454,
         39999,
         {-17.4028f, -0.906689f, -7.79851f},
         {17.4172f, 15.6533f, 7.80149f}},
        {"bunny.ply",
         69451,
         34834,
         {-0.0946899f, 0.0329874f, -0.0618736f},
         {0.0610091f, 0.187321f, 0.0587997f}},
        {"sibenik.ply", 75284, 40979, {-20.1411f, -15.3123f, -8.4968f}, {20.1411f, 15.3f, 8.4968f}},
        {"dragon.ply",
         871414,
         437645,
         {-0.108324f, 0.0527295f, -0.0504143f},
         {0.0965662f, 0.197173f, 0.0412075f}},
    };
    for (const Row& r : rows) {
        SCOPED_TRACE(r.file);
        const Scene s = load_scene(std::string(THICKET_SHARED_SCENES) + "/" + r.file);
        EXPECT_EQ(s.primitive_count(), r.tris);
        EXPECT_EQ(s.mesh.positions.size(), r.verts);
        const Aabb b = s.bounds();
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(b.min[a], r.lo[a], 1e-3f) << a;
            EXPECT_NEAR(b.max[a], r.hi[a], 1e-3f) << a;
        }
    }
}

TEST(LoaderShared, CornellObjAndPlyMatchBuiltin) {
    if (!shared_scenes_present()) GTEST_SKIP() << "../shared/scenes not found: " << THICKET_SHARED_SCENES;
    const Scene builtin = load_scene("cornell");
    const Scene obj = load_scene(std::string(THICKET_SHARED_SCENES) + "/CornellBox-Original.obj");
    const Scene ply = load_scene(std::string(THICKET_SHARED_SCENES) + "/cornell-box.ply");
    ASSERT_EQ(obj.primitive_count(), 36u);
    ASSERT_EQ(ply.primitive_count(), 36u);
    for (uint32_t t = 0; t < 36; ++t)
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(obj.mesh.vertex(t, c), builtin.mesh.vertex(t, c)) << t << " " << c;
            EXPECT_EQ(ply.mesh.vertex(t, c), builtin.mesh.vertex(t, c)) << t << " " << c;
        }
    EXPECT_EQ(obj.mesh.positions, builtin.mesh.positions);
    EXPECT_EQ(obj.mesh.indices, builtin.mesh.indices);
    EXPECT_EQ(obj.fingerprint(), builtin.fingerprint());
    EXPECT_EQ(ply.fingerprint(), builtin.fingerprint());
}

}  // namespace
}  // namespace thicket::loader_scene_test
