// OBJ loader tests: polygons with materials, a missing .mtl, errors that name the file.
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

namespace thicket {
namespace {

using namespace loader_test;

// ---- OBJ ---------------------------------------------------------------------------------------

const char* quad_obj =
    "mtllib quads.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0\n"
    "f 1 2 3\n"                // before any usemtl: the default material
    "usemtl red\nf 1 2 3 4\n"  // quad
    "g second\nusemtl glow\nf 1/1 2/2 3/3 5/4 4/5\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0.5 1\nvt 0 1\n";
const char* quad_mtl =
    "newmtl red\nKd 0.9 0.1 0.05\nKs 0.5 0.5 0.5\nNs 32\nNi 1.45\n"
    "newmtl glow\nKd 0.2 0.3 0.4\nKe 17 12 4\n";

TEST(LoaderObj, QuadsAndPentagonsWithMaterials) {
    TempDir tmp;
    tmp.file("quads.mtl", quad_mtl);
    const TriangleMesh m = load_obj(tmp.file("quads.obj", quad_obj));
    EXPECT_EQ(m.positions.size(), 5u);
    const std::vector<uint32_t> expected = {0, 1, 2, 0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 4, 0, 4, 3};
    EXPECT_EQ(m.indices, expected);
    ASSERT_EQ(m.materials.size(), 3u);
    EXPECT_EQ(m.materials[0].name, "red");
    EXPECT_EQ(m.materials[0].diffuse, Vec3(0.9f, 0.1f, 0.05f));
    EXPECT_EQ(m.materials[0].specular, Vec3(0.5f, 0.5f, 0.5f));
    EXPECT_FLOAT_EQ(m.materials[0].shininess, 32.0f);
    EXPECT_FLOAT_EQ(m.materials[0].ior, 1.45f);
    EXPECT_EQ(m.materials[1].name, "glow");
    EXPECT_EQ(m.materials[1].emission, Vec3(17, 12, 4));
    EXPECT_EQ(m.materials[2].name, "default");
    const std::vector<uint32_t> ids = {2, 0, 0, 1, 1, 1};
    EXPECT_EQ(m.material_ids, ids);
}

TEST(LoaderObj, MissingMtlIsOnlyAWarning) {
    TempDir tmp;
    const TriangleMesh m = load_obj(tmp.file("nomtl.obj", quad_obj));
    EXPECT_EQ(m.triangle_count(), 6u);
    EXPECT_TRUE(m.materials.empty());
    EXPECT_TRUE(m.material_ids.empty());
}

TEST(LoaderObj, ErrorsNameTheFile) {
    TempDir tmp;
    const std::string missing = tmp.dir() + "/missing.obj";
    expect_error([&] { load_obj(missing); }, missing, {});
    expect_error([&] { load_scene(missing); }, missing, {"no such file"});
    const std::string range = tmp.file("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n");
    expect_error([&] { load_obj(range); }, range, {"face 1", "out of range"});
    const std::string relative = tmp.file("rel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
    expect_error([&] { load_obj(relative); }, relative, {"face 0"});
    const std::string zero = tmp.file("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    expect_error([&] { load_obj(zero); }, zero, {});
}

}  // namespace
}  // namespace thicket
