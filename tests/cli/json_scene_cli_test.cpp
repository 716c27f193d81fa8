// JSON scenes through the `thicket` command: one scene holding a mesh and every shape kind is
// accepted by info, trace, render and bench; trace answers with ids in file order and agrees with
// brute force in-process; the normal view is the same picture through different structures; a bad
// scene fails with a message naming the shape and field and writes nothing.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>
#include <vector>

#include "support/cli_dir_test.h"
#include "support/png_read.h"
#include "thicket/accel/registry.h"
#include "thicket/util/npy.h"

namespace json_scene_cli_test {


namespace fs = std::filesystem;
using namespace thicket;
using thicket::testing::run_thicket;
using thicket::testing::shell_quote;

namespace {

// Ids in file order: the quad's 2 triangles (0 below its diagonal, 1 above), sphere 2, torus 3, teapot patches 4..35,
// subdivision 36, implicit 37, blobs 38, julia 39, mandelbulb 40. Shapes sit along x, 3 apart.
constexpr const char* kScene = R"({"shapes": [
  {"type": "mesh", "file": "quad.obj"},
  {"type": "sphere", "center": [0, 0, 0], "radius": 1},
  {"type": "torus", "center": [3, 0, 0], "axis": [0, 0, 1], "major_radius": 1, "minor_radius": 0.3},
  {"type": "teapot-patches", "transform": [0.4,0,0,6, 0,0.4,0,-0.6, 0,0,0.4,0, 0,0,0,1]},
  {"type": "subdivision", "cage": "cube", "level": 2, "transform": [0.7,0,0,9, 0,0.7,0,0, 0,0,0.7,0, 0,0,0,1]},
  {"type": "implicit", "surface": "tangle-cube", "center": [12, 0, 0], "scale": 0.4},
  {"type": "blobs", "centers": [[0, 0, 0], [0.5, 0, 0]], "radii": [1, 1], "threshold": 0.3, "center": [15, 0, 0]},
  {"type": "julia", "center": [18, 0, 0]},
  {"type": "mandelbulb", "center": [21, 0, 0]}
]})";

class JsonSceneCli : public thicket::testing::CliDirTest {
protected:
    void SetUp() override {
        CliDirTest::SetUp();
        if (IsSkipped()) return;
        // A quad at z = -5 behind the row of shapes, from x = -2 to 23.
        write("quad.obj", "v -2 -2 -5\nv 23 -2 -5\nv 23 2 -5\nv -2 2 -5\nf 1 2 3 4\n");
        write("scene.json", kScene);
    }
};

TEST_F(JsonSceneCli, InfoCountsEveryKind) {
    const auto r = run_thicket("info " + q("scene.json"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("39 (1 sphere, 1 torus, 32 bezier, 1 subdivision, 1 implicit, 1 blobs, 1 julia, 1 mandelbulb)"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("41 (ids in file order"), std::string::npos) << r.output;
}

TEST_F(JsonSceneCli, TraceAnswersWithFileOrderIdsLikeBruteForce) {
    // One ray down -z at the centre of each shape (from z = 5), one at the quad, one that misses.
    const float xs[] = {0, 3.0f + 1.0f, 6.37f, 9, 12.0f + 0.65f, 15.25f, 18, 21, -1.5f, 30};
    std::vector<float> rows;
    for (float x : xs) rows.insert(rows.end(), {x, 0.3f, 5, 0, 0, -1, 0, kInfinity});
    write_npy_f32((dir_ / "rays.npy").string(), {rows.size() / 8, 8}, rows);

    const Scene scene = load_scene((dir_ / "scene.json").string());
    const auto brute = build_accel("brute", scene);
    const uint32_t want_prim[] = {2, 3, kNoPrim, 36, 37, 38, 39, 40, 1, kNoPrim};
    for (const char* accel : {"bvh", "kdtree", "grid", "bsp"}) {
        SCOPED_TRACE(accel);
        const auto r = run_thicket(std::string("trace ") + q("scene.json") + " --accel " + accel + " --rays " + q("rays.npy") +
                                   " --force -o " + q("hits.npy"));
        ASSERT_EQ(r.code, 0) << r.output;
        const std::vector<Hit> hits = read_npy_hits((dir_ / "hits.npy").string());
        ASSERT_EQ(hits.size(), std::size(xs));
        for (size_t i = 0; i < hits.size(); ++i) {
            const Ray ray{{rows[8 * i], rows[8 * i + 1], rows[8 * i + 2]}, 0.0f, {0, 0, -1}, kInfinity};
            const Hit want = brute->intersect(ray);
            EXPECT_EQ(hits[i].prim, want.prim) << "ray " << i;
            EXPECT_EQ(hits[i].t, want.t) << "ray " << i;
            if (want_prim[i] != kNoPrim) {
                EXPECT_EQ(hits[i].prim, want_prim[i]) << "ray " << i;
            }
        }
        // The teapot's ray hits one of its 32 patches (ids 4..35).
        EXPECT_GE(hits[2].prim, 4u);
        EXPECT_LE(hits[2].prim, 35u);
    }
}

TEST_F(JsonSceneCli, NormalViewIsTheSamePictureThroughEveryStructure) {
    std::vector<std::vector<unsigned char>> images;
    for (const char* accel : {"brute", "bvh", "kdtree", "octree", "bih"}) {
        const std::string out = std::string(accel) + ".png";
        const auto r = run_thicket("render " + q("scene.json") + " --accel " + accel +
                                   " --size 160x40 --camera 10.5,0,9,10.5,0,0,40 -o " + q(out));
        ASSERT_EQ(r.code, 0) << accel << ": " << r.output;
        int w = 0, h = 0;
        std::string why;
        images.push_back(thicket::testing::read_png_rgb((dir_ / out).string(), w, h, why));
        ASSERT_FALSE(images.back().empty()) << accel << ": " << why;
        ASSERT_EQ(w, 160);
    }
    size_t background = 0;
    for (size_t i = 0; i < images[0].size(); i += 3) background += images[0][i] == 0 && images[0][i + 1] == 0 && images[0][i + 2] == 0;
    EXPECT_LT(background, images[0].size() / 3 * 3 / 4) << "the shapes and the quad fill a good part of the view";
    for (size_t k = 1; k < images.size(); ++k) {
        size_t differ = 0;
        for (size_t i = 0; i < images[0].size(); ++i) differ += images[k][i] != images[0][i];
        // Patch borders shared by two patches are ties whose normals differ in the last bits.
        EXPECT_LE(differ, images[0].size() / 1000) << "structure " << k << " differs from brute force";
    }
}

TEST_F(JsonSceneCli, BenchLeavesEmbreeOutAndCountsPrimitives) {
    const auto r = run_thicket("bench " + q("scene.json") + " --accel bvh --sets primary --size 24x16 --reps 1 --json " +
                               q("b.json"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("embree  left out for this scene"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("41 primitives (2 triangles, 39 shapes)"), std::string::npos) << r.output;
    std::ifstream in(dir_ / "b.json");
    const std::string json{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_NE(json.find("\"shapes\": 39"), std::string::npos) << json.substr(0, 400);

    // The JSON file is never overwritten without --force, and the refusal comes before the work.
    write("b.json", "mine");
    const std::string again = "bench " + q("scene.json") + " --accel bvh --sets primary --size 8x8 --reps 1 --json " + q("b.json");
    auto refused = run_thicket(again);
    EXPECT_EQ(refused.code, 1) << refused.output;
    EXPECT_NE(refused.output.find("already exists (use --force"), std::string::npos) << refused.output;
    EXPECT_EQ(refused.output.find("bvh "), std::string::npos) << "nothing was measured: " << refused.output;
    std::ifstream mine(dir_ / "b.json");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(mine), std::istreambuf_iterator<char>()), "mine");
    const auto forced = run_thicket(again + " --force");
    EXPECT_EQ(forced.code, 0) << forced.output;
}

TEST_F(JsonSceneCli, BuiltInTeapotPatchesRenders) {
    const auto r = run_thicket("render teapot-patches --size 48x32 -o " + q("t.png"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir_ / "t.png"));
}

TEST_F(JsonSceneCli, BadSceneNamesShapeAndFieldAndWritesNothing) {
    write("bad.json", R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1},
                                      {"type": "julia", "iterations": 2.5}]})");
    const auto r = run_thicket("render " + q("bad.json") + " -o " + q("out.png"));
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("shape 1 (julia): field 'iterations': must be an integer"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "out.png"));
}

}  // namespace

namespace {

/// Instances: `info` counts geometries, instances, unique and instanced primitives; `bench` and
/// `render` take the scene (the bench's Embree rows trace Embree's own instances, and every
/// structure must agree with them on the shadow rays, which start on surfaces).
class InstancedSceneCli : public thicket::testing::CliDirTest {
protected:
    void SetUp() override {
        CliDirTest::SetUp();
        if (IsSkipped()) return;
        write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
        write("scene.json", R"({"shapes": [{"type": "mesh", "file": "quad.obj"}],
            "instances": [{"shape": 0, "transform": [4,0,0,-2, 0,0,1,0, 0,-4,0,2]},
                          {"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0]},
                          {"shape": 0, "transform": [-1,0.5,0,1, 0,1,0,0, 0,0,1,0.5]}]})");
    }
};

TEST_F(InstancedSceneCli, InfoCountsInstancesAndBenchAndRenderTakeThem) {
    const auto info = run_thicket("info " + q("scene.json"));
    ASSERT_EQ(info.code, 0) << info.output;
    EXPECT_NE(info.output.find("geometries           1\n"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("instances            3, placing 1 of the geometries"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("unique primitives    2 "), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("instanced primitives 6 "), std::string::npos) << info.output;
    const auto render = run_thicket("render " + q("scene.json") + " --size 32x24 -o " + q("out.png"));
    ASSERT_EQ(render.code, 0) << render.output;
    const auto bench = run_thicket("bench " + q("scene.json") + " -a bvh --sets primary,shadow --size 32x24 --reps 1");
    ASSERT_EQ(bench.code, 0) << bench.output;
    // Agreement with Embree's instanced scene: a row that differs shows "99.x (N)", one whose
    // rays the rounding arbiter settled "100 [N]"; neither is allowed here (none of these rays
    // passes within rounding of a quad's outer edge, and the diagonal is no excuse: a settled ray
    // would be a transform one side got wrong, forgiven).
    EXPECT_FALSE(std::regex_search(bench.output, std::regex(R"(\d\.\d+ \(\d+\))"))) << bench.output;
    EXPECT_FALSE(std::regex_search(bench.output, std::regex(R"(\d \[[\d,]+\])"))) << bench.output;
    if (bench.output.find("built without") == std::string::npos) {
        EXPECT_NE(bench.output.find("embree-high"), std::string::npos) << bench.output;
    }
}

}  // namespace

}  // namespace json_scene_cli_test
