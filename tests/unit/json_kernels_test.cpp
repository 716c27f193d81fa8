// JSON scenes with the complex kernels (docs/shapes.md): each type builds the same kernel as the
// C++ API with those parameters (same hits), patch sets take one id per patch, transforms move
// control points and cages, the built-in `teapot-patches` scene, and every bad value is an error
// that names the shape and the field.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "support/temp_dir.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/prims/control_mesh.h"
#include "thicket/prims/teapot_patches.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::json_kernels_test {
namespace {

class Dir : public testing::TempDir {
public:
    Dir() : testing::TempDir("thicket_json_kernels") {
        // A cube cage as an OBJ of quads.
        file("cage.obj",
             "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
             "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
        // The same cube as an ASCII PLY of quads (0-based).
        file("cage.ply",
             "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 6\nproperty list uchar int vertex_indices\nend_header\n"
             "-1 -1 -1\n1 -1 -1\n1 1 -1\n-1 1 -1\n-1 -1 1\n1 -1 1\n1 1 1\n-1 1 1\n"
             "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n");
    }
    Scene load(const std::string& shapes_list) const {
        return load_scene(file("scene.json", "{\"shapes\": [" + shapes_list + "]}"));
    }
    void expect_error(const std::string& shape, const std::vector<std::string>& fragments) const {
        SCOPED_TRACE(shape);
        try {
            load(shape);
            ADD_FAILURE() << "no error";
        } catch (const Error& e) {
            const std::string what = e.what();
            for (const std::string& f : fragments)
                EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
        }
    }
};

/// The hit of kernel `s` along `ray` (t < 0 for none).
float kernel_t(const Shape& s, const Ray& ray) {
    ShapeHit h;
    return std::visit([&](const auto& k) { return k.intersect(ray, kInfinity, h); }, s) ? h.t : -1.0f;
}

/// Rays from a ring around `center` towards it; the JSON-built and API-built kernels must agree
/// (the JSON values are chosen exact in float, as the parser reads some fields as floats).
void expect_same_hits(const Shape& a, const Shape& b, Vec3 center, float radius) {
    int hits = 0;
    for (int i = 0; i < 24; ++i) {
        const float phi = 0.2618f * float(i);
        const Vec3 o = center + Vec3{std::cos(phi), 0.3f * std::sin(3.0f * phi), std::sin(phi)} * (3.0f * radius);
        const Vec3 target = center + Vec3{0.1f * std::sin(float(i)), 0.2f * std::cos(float(i)), 0.0f} * radius;
        const Ray ray{o, 0.0f, target - o, kInfinity};
        const float ta = kernel_t(a, ray), tb = kernel_t(b, ray);
        EXPECT_EQ(ta, tb) << shape_name(a) << " ray " << i;
        hits += ta >= 0.0f;
    }
    EXPECT_GE(hits, 6) << shape_name(a) << ": too few hits for the comparison to mean anything";
}

TEST(JsonKernels, EachTypeBuildsTheKernelOfItsFields) {
    Dir dir;
    const Scene s = dir.load(R"(
        {"type": "implicit", "surface": "tangle-cube", "center": [1, 2, 3], "scale": 0.5},
        {"type": "implicit", "surface": "barth-sextic", "clip": 1.2, "method": "sphere-tracing", "epsilon": 1e-5,
         "max_steps": 5000},
        {"type": "blobs", "centers": [[0, 0, 0], [0.75, 0.25, 0]], "radii": [1, 0.75], "weights": [1, 0.875],
         "threshold": 0.25, "center": [-3, 0, 0], "scale": 2},
        {"type": "julia", "c": [-0.2, 0.6, 0.2, 0.2], "w": 0.125, "iterations": 9, "epsilon": 0.001953125, "step_factor": 0.875,
         "center": [0, 5, 0], "scale": 1.5},
        {"type": "mandelbulb", "power": 6, "iterations": 7, "max_steps": 4000, "center": [0, -5, 0]},
        {"type": "subdivision", "cage": "cube", "level": 2, "transform": [2,0,0,10, 0,2,0,0, 0,0,2,0, 0,0,0,1]})");
    ASSERT_EQ(s.shapes.size(), 6u);
    EXPECT_EQ(s.primitive_count(), 6u);

    ImplicitOptions tangle;
    tangle.center = {1, 2, 3};
    tangle.scale = 0.5f;
    expect_same_hits(s.shapes[0], Implicit("tangle-cube", tangle), {1, 2, 3}, 1.1f);

    ImplicitOptions barth;
    barth.method = ImplicitMethod::sphere_tracing;
    barth.epsilon = 1e-5;
    barth.max_steps = 5000;
    expect_same_hits(s.shapes[1], Implicit("barth-sextic", barth, 1.2), {0, 0, 0}, 1.2f);

    ImplicitOptions blobs;
    blobs.center = {-3, 0, 0};
    blobs.scale = 2.0f;
    expect_same_hits(s.shapes[2], Blobs(BlobSum{{Blob{{0, 0, 0}, 1.0, 1.0}, Blob{{0.75, 0.25, 0}, 0.75, 0.875}}, 0.25}, blobs),
                     {-3, 0, 0}, 1.5f);

    Julia::Params julia;
    julia.c = {-0.2, 0.6, 0.2, 0.2};
    julia.w = 0.125;
    julia.march.iterations = 9;
    julia.march.epsilon = 0.001953125;
    julia.march.step_factor = 0.875;
    julia.march.center = {0, 5, 0};
    julia.march.scale = 1.5f;
    expect_same_hits(s.shapes[3], Julia(julia), {0, 5, 0}, 1.0f);

    Mandelbulb::Params bulb;
    bulb.power = 6;
    bulb.march.iterations = 7;
    bulb.march.max_steps = 4000;
    bulb.march.center = {0, -5, 0};
    expect_same_hits(s.shapes[4], Mandelbulb(bulb), {0, -5, 0}, 0.8f);

    ControlMesh cage = cube_control_mesh();
    for (Vec3& p : cage.positions) p = Vec3{10, 0, 0} + p * 2.0f;
    expect_same_hits(s.shapes[5], SubdivisionSurface(cage, 2), {10, 0, 0}, 1.5f);
    EXPECT_EQ(std::get<SubdivisionSurface>(s.shapes[5]).level(), 2);
}

TEST(JsonKernels, SubdivisionCagesFromObjPlyInlineAndDefaultLevel) {
    Dir dir;
    const Scene s = dir.load(R"(
        {"type": "subdivision", "file": "cage.obj"},
        {"type": "subdivision", "file": "cage.ply"},
        {"type": "subdivision", "positions": [[-1,-1,-1],[1,-1,-1],[1,1,-1],[-1,1,-1],[-1,-1,1],[1,-1,1],[1,1,1],[-1,1,1]],
         "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]], "level": 3},
        {"type": "subdivision", "cage": "cube"})");
    ASSERT_EQ(s.shapes.size(), 4u);
    for (const Shape& shape : s.shapes) EXPECT_EQ(std::get<SubdivisionSurface>(shape).level(), 3) << "3 is the default";

    // The PLY's polygons are rebuilt from its fans: the same cage as the OBJ's.
    const ControlMesh obj = load_control_mesh(dir.dir() + "/cage.obj"), ply = load_control_mesh(dir.dir() + "/cage.ply");
    EXPECT_EQ(obj.positions, ply.positions);
    EXPECT_EQ(obj.face_sizes, ply.face_sizes);
    EXPECT_EQ(obj.indices, ply.indices);

    ControlMesh inline_cage;
    inline_cage.positions = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
    inline_cage.face_sizes = {4, 4, 4, 4, 4, 4};
    inline_cage.indices = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    expect_same_hits(s.shapes[0], SubdivisionSurface(obj, 3), {0, 0, 0}, 1.0f);
    expect_same_hits(s.shapes[1], SubdivisionSurface(obj, 3), {0, 0, 0}, 1.0f);
    expect_same_hits(s.shapes[2], SubdivisionSurface(inline_cage, 3), {0, 0, 0}, 1.0f);
    expect_same_hits(s.shapes[3], SubdivisionSurface(cube_control_mesh(), 3), {0, 0, 0}, 1.0f);
}

TEST(JsonKernels, PatchSetsTakeOneIdPerPatch) {
    Dir dir;
    const Scene s = dir.load(R"(
        {"type": "sphere", "center": [0, 0, -20], "radius": 1},
        {"type": "teapot-patches", "transform": [2,0,0,0, 0,2,0,1, 0,0,2,0, 0,0,0,1]},
        {"type": "bezier", "control_points": [[0,0,0],[1,0,0],[2,0,0],[3,0,0], [0,1,0],[1,1,1],[2,1,1],[3,1,0],
                                              [0,2,0],[1,2,1],[2,2,1],[3,2,0], [0,3,0],[1,3,0],[2,3,0],[3,3,0]],
         "transform": [1,0,0,20, 0,1,0,0, 0,0,1,0, 0,0,0,1]})");
    ASSERT_EQ(s.primitive_count(), 1u + kTeapotPatchCount + 1u);
    const std::vector<BezierPatch> teapot = teapot_patches();
    for (int p = 0; p < kTeapotPatchCount; ++p) {
        const BezierPatch& got = std::get<BezierPatch>(s.shapes[1 + p]);
        for (int k = 0; k < 16; ++k) {
            const Vec3 want = teapot[p].control_points()[k] * 2.0f + Vec3{0, 1, 0};
            ASSERT_EQ(got.control_points()[k], want) << "patch " << p << " point " << k;
        }
    }
    const BezierPatch& flat = std::get<BezierPatch>(s.shapes.back());
    EXPECT_EQ(flat.control_point(1, 1), (Vec3{21, 1, 1})) << "index 4 j + i, moved by the transform";

    // Through a structure: the ids are the file order (sphere 0, patches 1..32, the patch 33).
    const auto bvh = build_accel("bvh", s);
    EXPECT_EQ(bvh->intersect({{0, 0, 0}, 0.0f, {0, 0, -1}, kInfinity}).prim, 0u);
    const Hit body = bvh->intersect({{0, 3, 20}, 0.0f, {0, 0, -1}, kInfinity});  // the body's front, 2x size
    ASSERT_TRUE(body.found());
    EXPECT_GE(body.prim, 1u);
    EXPECT_LE(body.prim, 32u);
    EXPECT_EQ(bvh->intersect({{21.5f, 1.5f, 10}, 0.0f, {0, 0, -1}, kInfinity}).prim, 33u);
}

TEST(JsonKernels, BuiltInTeapotPatchesScene) {
    const Scene s = load_scene("teapot-patches");
    EXPECT_EQ(s.shapes.size(), size_t(kTeapotPatchCount));
    EXPECT_EQ(s.mesh.triangle_count(), 0u);
    const Aabb b = s.bounds();
    EXPECT_NEAR(b.min.y, 0.0f, 1e-4f);
    EXPECT_NEAR(b.max.y, 3.15f, 1e-3f);
    const auto bvh = build_accel("bvh", s);
    const Hit h = bvh->intersect({{0, 1.5f, 10}, 0.0f, {0, 0, -1}, kInfinity});
    ASSERT_TRUE(h.found());
    EXPECT_EQ(teapot_group(int(h.prim)), TeapotGroup::Body);
    EXPECT_GT(10.0f - h.t, 1.8f) << "the body's radius at mid-height";
    EXPECT_LE(10.0f - h.t, 2.0f) << "the body is at most 2 wide";
}

TEST(JsonKernels, BadValuesNameTheShapeAndField) {
    Dir dir;
    dir.expect_error(R"({"type": "bezier", "control_points": [[0,0,0]]})",
                     {"shape 0 (bezier)", "field 'control_points'", "array of 16 points", "of 1"});
    dir.expect_error(R"({"type": "bezier", "control_points": [[0,0,0],[1,0,0],[2,0,0],[3,0,0],[0,1,0],[1,1,1],[2,1,1],
                          [3,1,0],[0,2,0],[1,2,1],[2,2,1],[3,2,0],[0,3,0],[1,3,0],[2,3,0],[3,3]]})",
                     {"shape 0 (bezier)", "field 'control_points'", "element 15", "point"});
    dir.expect_error(R"({"type": "teapot-patches", "scale": 2})", {"shape 0 (teapot-patches)", "field 'scale'", "unknown field"});
    dir.expect_error(R"({"type": "subdivision", "level": 2})", {"shape 0 (subdivision)", "exactly one cage"});
    dir.expect_error(R"({"type": "subdivision", "cage": "cube", "file": "cage.obj"})", {"shape 0 (subdivision)", "exactly one cage"});
    dir.expect_error(R"({"type": "subdivision", "cage": "sphere"})", {"field 'cage'", "unknown built-in cage 'sphere'", "cube"});
    dir.expect_error(R"({"type": "subdivision", "cage": "cube", "level": 9})", {"field 'level'", "from 0 to 8", "9"});
    dir.expect_error(R"({"type": "subdivision", "cage": "cube", "level": 2.5})", {"field 'level'", "must be an integer"});
    dir.expect_error(R"({"type": "subdivision", "cage": "cube", "faces": [[0,1,2]]})", {"field 'faces'", "only goes with 'positions'"});
    dir.expect_error(R"({"type": "subdivision", "positions": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,7]]})",
                     {"shape 0 (subdivision)", "face 0", "7"});
    dir.expect_error(R"({"type": "subdivision", "positions": [[0,0,0],[1,0,0],[0,1,0]], "faces": [[0,1,-2]]})",
                     {"shape 0 (subdivision)", "field 'faces'", "indices"});
    dir.expect_error(R"({"type": "subdivision", "file": "missing.obj"})", {"field 'file'", "no such file"});
    dir.expect_error(R"({"type": "subdivision", "file": "scene.json"})", {"field 'file'", "OBJ or PLY", "'.json'"});
    dir.expect_error(R"({"type": "implicit", "surface": "klein-bottle"})",
                     {"shape 0 (implicit)", "field 'surface'", "tangle-cube", "barth-sextic", "klein-bottle"});
    dir.expect_error(R"({"type": "implicit", "surface": "tangle-cube", "clip": 2})", {"field 'clip'", "barth-sextic"});
    dir.expect_error(R"({"type": "implicit", "surface": "tangle-cube", "method": "newton"})",
                     {"field 'method'", "interval", "sphere-tracing", "newton"});
    dir.expect_error(R"({"type": "implicit", "surface": "tangle-cube", "scale": 0})", {"field 'scale'", "positive"});
    dir.expect_error(R"({"type": "implicit", "surface": "tangle-cube", "epsilon": -1})", {"field 'epsilon'", ">= 0"});
    dir.expect_error(R"({"type": "implicit", "surface": "tangle-cube", "max_steps": 0})", {"field 'max_steps'", "from 1"});
    dir.expect_error(R"({"type": "blobs", "centers": [[0,0,0],[1,0,0]], "radii": [1]})",
                     {"shape 0 (blobs)", "field 'radii'", "array of 2 numbers", "of 1"});
    dir.expect_error(R"({"type": "blobs", "centers": [[0,0,0],[1,0,0]], "radii": [1, -1]})", {"field 'radii'", "element 1", "positive"});
    dir.expect_error(R"({"type": "blobs", "centers": [[0,0,0]], "radii": [1], "weights": [0]})", {"field 'weights'", "positive"});
    dir.expect_error(R"({"type": "blobs", "centers": [], "radii": []})", {"field 'centers'", "one or more"});
    dir.expect_error(R"({"type": "julia", "c": [0.1, 0.2, 0.3]})", {"shape 0 (julia)", "field 'c'", "array of 4"});
    dir.expect_error(R"({"type": "julia", "step_factor": 1.5})", {"field 'step_factor'", "(0, 1]"});
    dir.expect_error(R"({"type": "julia", "iterations": 0})", {"field 'iterations'", "from 1 to 1000"});
    dir.expect_error(R"({"type": "julia", "w": 5})", {"shape 0 (julia)", "slice"});
    dir.expect_error(R"({"type": "mandelbulb", "power": 40})", {"shape 0 (mandelbulb)", "power"});
    dir.expect_error(R"({"type": "mandelbulb", "bailout": 1})", {"shape 0 (mandelbulb)", "bailout"});
    dir.expect_error(R"({"type": "mandelbulb", "colour": 1})", {"shape 0 (mandelbulb)", "field 'colour'", "unknown field", "'power'"});
}

}  // namespace
}  // namespace thicket::json_kernels_test
