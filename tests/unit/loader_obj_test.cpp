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

namespace thicket::loader_obj_test {
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
    "newmtl red\nKd 0.9 0.1 0.05\nKs 0.5 0.5 0.5\nNs 32\nNi 1.45\nd 0.25\nillum 7\n"
    "newmtl glow\nKd 0.2 0.3 0.4\nKe 17 12 4\nTr 0.125\n";

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
    EXPECT_FLOAT_EQ(m.materials[0].dissolve, 0.25f);
    EXPECT_EQ(m.materials[0].illum, 7);
    EXPECT_EQ(m.materials[1].name, "glow");
    EXPECT_EQ(m.materials[1].emission, Vec3(17, 12, 4));
    EXPECT_FLOAT_EQ(m.materials[1].dissolve, 0.875f);  // Tr is 1 - d
    EXPECT_EQ(m.materials[1].illum, -1);
    EXPECT_EQ(m.materials[2].name, "default");
    const std::vector<uint32_t> ids = {2, 0, 0, 1, 1, 1};
    EXPECT_EQ(m.material_ids, ids);
}

TEST(LoaderObj, MtlOpacityAndIlluminationModelAreChecked) {
    for (const auto& [mtl, needle] : std::vector<std::pair<std::string, std::string>>{
             {"newmtl a\nd 1.5\n", "d: must be a number from 0 to 1 (opacity), got 1.5"},
             {"newmtl a\nillum 2.5\n", "illum: must be a whole number from 0 to 10 (illumination model), got 2.5"},
             {"newmtl a\nillum 11\n", "illum: must be a whole number from 0 to 10 (illumination model), got 11"}}) {
        TempDir tmp;
        tmp.file("quads.mtl", mtl);
        try {
            load_obj(tmp.file("quads.obj", quad_obj));
            ADD_FAILURE() << "accepted " << mtl;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("quads.mtl: line 2"), std::string::npos) << e.what();
        }
    }
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


// ---- issue 16: what tinyobjloader got silently wrong -------------------------------------------

// A polygon of n vertices around the unit circle, then a triangle: the file of the issue's
// "256-gon then a triangle" reproduction for any n.
std::string polygon_then_triangle(int n) {
    std::string text;
    for (int i = 0; i < n; ++i)
        text += "v " + std::to_string(std::cos(0.01 * i)) + " " + std::to_string(std::sin(0.01 * i)) + " 0\n";
    text += "v 0 0 1\nv 1 0 1\nv 0 1 1\nf";
    for (int i = 1; i <= n; ++i) {
        text += ' ';
        text += std::to_string(i);  // not " " + to_string(): GCC 12 warns falsely (-Wrestrict) on that
    }
    text += "\nf " + std::to_string(n + 1) + " " + std::to_string(n + 2) + " " + std::to_string(n + 3) + "\n";
    return text;
}

TEST(LoaderObj, PolygonsOf256AndMoreVerticesKeepTheFacesAfterThem) {
    TempDir tmp;
    for (int n : {255, 256, 300, 1000}) {
        const TriangleMesh m = load_obj(tmp.file("poly" + std::to_string(n) + ".obj", polygon_then_triangle(n)));
        ASSERT_EQ(m.triangle_count(), size_t(n - 2 + 1)) << n << "-gon";
        // The fan: v0 v(k-1) v(k); the triangle after it is intact.
        EXPECT_EQ(m.indices[3 * size_t(n - 3) + 2], uint32_t(n - 1));
        const std::vector<uint32_t> last(m.indices.end() - 3, m.indices.end());
        EXPECT_EQ(last, (std::vector<uint32_t>{uint32_t(n), uint32_t(n + 1), uint32_t(n + 2)}));
    }
}

TEST(LoaderObj, IndicesBeyond32BitsAreRefusedNotWrapped) {
    TempDir tmp;
    const std::string wrap = tmp.file("wrap.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967297\n");
    expect_error([&] { load_obj(wrap); }, wrap, {"line 4", "4294967297", "out of range"});
    const std::string huge = tmp.file("huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n");
    expect_error([&] { load_obj(huge); }, huge, {"out of range"});
}

TEST(LoaderObj, TwoToThe31IsAnOutOfRangeIndexNotARelativeOne) {
    TempDir tmp;
    const std::string p = tmp.file("big.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2147483648\n");
    try {
        load_obj(p);
        ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("2147483648 is out of range (3 vertices)"), std::string::npos) << what;
        EXPECT_EQ(what.find("relative"), std::string::npos) << what;
    }
}

TEST(LoaderObj, GarbageIsRefusedWithTheLine) {
    TempDir tmp;
    const std::string abc = tmp.file("abc.obj", "v abc def ghi\n");
    expect_error([&] { load_obj(abc); }, abc, {"line 1", "'abc' is not a number"});
    const std::string one = tmp.file("one.obj", "# a comment\nv 1\n");
    expect_error([&] { load_obj(one); }, one, {"line 2", "x y z"});
    const std::string two = tmp.file("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
    expect_error([&] { load_obj(two); }, two, {"line 3", "at least 3"});
    const std::string slash = tmp.file("slash.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n");
    expect_error([&] { load_obj(slash); }, slash, {"line 4", "'1/x'"});
    std::mt19937 rng(16);
    std::string noise(4096, '\0');
    for (char& c : noise) c = char(rng());
    const std::string random = tmp.file("random.obj", noise);
    expect_error([&] { load_obj(random); }, random, {"line"});
    expect_error([&] { load_scene(random); }, random, {"line"});
}

TEST(LoaderObj, StatementsThicketIgnoresAreSkipped) {
    TempDir tmp;
    const TriangleMesh m = load_obj(tmp.file("skip.obj",
        "o thing\ng a b\ns off\nv 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv +0 1e0 0\nvt 0 0\nvn 0 0 1\n"
        "f 1/1/1 2//1 \\\n 3/1\nl 1 2\n"));
    EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(m.positions[2], Vec3(0, 1, 0));
}

TEST(LoaderObj, AMaterialLibraryThatIsADeviceIsRefused) {
    TempDir tmp;
    const std::string p = tmp.file("zero.obj", "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_error([&] { load_obj(p); }, p, {"/dev/zero", "character device"});
    const std::string bad = tmp.file("badmtl.obj", "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    tmp.file("bad.mtl", "newmtl m\nKd red green blue\n");
    expect_error([&] { load_obj(bad); }, bad, {"bad.mtl: line 2", "'red'"});
}

}  // namespace
}  // namespace thicket::loader_obj_test
