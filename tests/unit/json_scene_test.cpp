// JSON scenes: the id order (triangles and shapes interleaved in file order), transforms and
// relative paths, reserved keys, every class of bad input (the message names the file, the shape
// and the field), and scenes with shapes through the registry (dispatch, normals, save/load).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "allocation_counter.h"
#include "support/temp_dir.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::json_scene_test {
namespace {

namespace fs = std::filesystem;

/// A temporary directory with two meshes: meshes/quad.obj (two triangles in z = 0) and tri.obj
/// (one at z = 5).
class TempDir : public testing::TempDir {
public:
    TempDir() : testing::TempDir("thicket_json") {
        fs::create_directories(fs::path(dir()) / "meshes");
        file("meshes/quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
        file("tri.obj", "v 0 0 5\nv 1 0 5\nv 0 1 5\nf 1 2 3\n");
    }
};

/// Loads `json` as a scene file and expects an Error naming the file and every fragment.
void expect_error(const TempDir& tmp, const std::string& json, const std::vector<std::string>& fragments) {
    const std::string path = tmp.file("scene.json", json);
    try {
        load_scene(path);
        ADD_FAILURE() << "no error for " << json;
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(path, 0), 0u) << "message does not start with the path: " << what;
        for (const std::string& f : fragments)
            EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
    }
}

std::string shapes(const std::string& list) { return "{\"shapes\": [" + list + "]}"; }

const char* kSphere = R"({"type": "sphere", "center": [0, 0, 10], "radius": 1})";
const char* kTorus = R"({"type": "torus", "center": [0, 0, -10], "axis": [0, 0, 2], "major_radius": 2, "minor_radius": 0.5})";

TEST(JsonScene, IdsCountShapesInFileOrder) {
    TempDir tmp;
    const std::string path = tmp.file(
        "scene.json", shapes(std::string(R"({"type": "mesh", "file": "meshes/quad.obj"}, )") + kSphere + ", " +
                             R"({"type": "mesh", "file": "tri.obj"}, )" + kTorus + ", " +
                             R"({"type": "sphere", "center": [5, 5, 5], "radius": 0.5})"));
    const Scene s = load_scene(path);
    EXPECT_EQ(s.name, path);
    ASSERT_EQ(s.primitive_count(), 6u);  // 2 + 1 + 1 + 1 + 1
    EXPECT_EQ(s.mesh.triangle_count(), 3u);
    ASSERT_EQ(s.shapes.size(), 3u);
    const PrimRef want[] = {{false, 0}, {false, 1}, {true, 0}, {false, 2}, {true, 1}, {true, 2}};
    for (uint32_t i = 0; i < 6; ++i) {
        EXPECT_EQ(s.locate(i).shape, want[i].shape) << i;
        EXPECT_EQ(s.locate(i).index, want[i].index) << i;
    }
    EXPECT_STREQ(shape_name(s.shapes[0]), "sphere");
    EXPECT_STREQ(shape_name(s.shapes[1]), "torus");
    const Torus& t = std::get<Torus>(s.shapes[1]);
    EXPECT_EQ(t.axis, (Vec3{0, 0, 1})) << "the axis is normalized";

    // Every structure answers with those ids.
    for (const char* spec : {"brute", "bvh", "bvh:isect=watertight"}) {
        SCOPED_TRACE(spec);
        const auto accel = build_accel(spec, s);
        EXPECT_EQ(accel->stats().primitives, 6u);
        EXPECT_EQ(accel->intersect({{0.7f, 0.2f, -1}, 0.0f, {0, 0, 1}, kInfinity}).prim, 0u);   // quad, 1st tri
        EXPECT_EQ(accel->intersect({{0.2f, 0.7f, -1}, 0.0f, {0, 0, 1}, kInfinity}).prim, 1u);   // quad, 2nd tri
        EXPECT_EQ(accel->intersect({{0, 0, 20}, 0.0f, {0, 0, -1}, kInfinity}).prim, 2u);        // sphere
        EXPECT_EQ(accel->intersect({{0.1f, 0.1f, 6}, 0.0f, {0, 0, -1}, kInfinity}).prim, 3u);   // tri.obj
        EXPECT_EQ(accel->intersect({{2, 0, -20}, 0.0f, {0, 0, 1}, kInfinity}).prim, 4u);        // torus
        EXPECT_EQ(accel->intersect({{5, 5, 9}, 0.0f, {0, 0, -1}, kInfinity}).prim, 5u);         // 2nd sphere
        // Along the torus's axis: through its hole, stopping before the quad at t = 20.
        EXPECT_FALSE(accel->occluded({{0.05f, 0.02f, -20}, 0.0f, {0, 0, 1}, 15.0f}));
        EXPECT_TRUE(accel->occluded({{0.05f, 0.02f, -20}, 0.0f, {0, 0, 1}, 25.0f}));
    }
}

TEST(JsonScene, NormalsOfTrianglesAndShapes) {
    TempDir tmp;
    const Scene s = load_scene(tmp.file("scene.json", shapes(std::string(R"({"type": "mesh", "file": "tri.obj"}, )") +
                                                                 kSphere + ", " + kTorus)));
    const auto accel = build_accel("bvh", s);
    const Ray down{{0.1f, 0.1f, 20}, 0.0f, {0, 0, -1}, kInfinity};
    Hit h = accel->intersect(down);  // the sphere's top, at (0.1, 0.1, ~11)
    ASSERT_EQ(h.prim, 1u);
    const Vec3 p = down.org + down.dir * h.t;
    const Vec3 want = normalize(p - Vec3{0, 0, 10});
    const Vec3 n = s.normal(down, h);
    EXPECT_NEAR(dot(n, want), 1.0f, 1e-6f);
    const Ray tri{{0.1f, 0.1f, 6}, 0.0f, {0, 0, -1}, 5.0f};  // below the sphere, onto the triangle at z = 5
    h = accel->intersect(tri);
    ASSERT_EQ(h.prim, 0u);
    EXPECT_EQ(s.normal(tri, h), (Vec3{0, 0, 1}));
    const Ray torus{{2, 0, -20}, 0.0f, {0, 0, 1}, kInfinity};  // the torus's -z side faces the ray
    h = accel->intersect(torus);
    ASSERT_EQ(h.prim, 2u);
    EXPECT_NEAR(s.normal(torus, h).z, -1.0f, 1e-5f);
    EXPECT_EQ(s.normal(torus, Hit{}), Vec3{}) << "a miss has no normal";
    EXPECT_EQ(s.geometric_normal(1), Vec3{}) << "geometric_normal is for triangles";
}

TEST(JsonScene, TransformAndRelativePaths) {
    TempDir tmp;
    fs::create_directories(fs::path(tmp.dir()) / "sub");
    // Scale by 2, translate by (10, 0, 0); the mesh path is relative to sub/, where the scene is.
    tmp.file("sub/m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Scene s = load_scene(tmp.file(
        "sub/scene.json",
        shapes(R"({"type": "mesh", "file": "m.obj", "transform": [2,0,0,10, 0,2,0,0, 0,0,2,0, 0,0,0,1]})")));
    ASSERT_EQ(s.mesh.triangle_count(), 1u);
    EXPECT_EQ(s.mesh.vertex(0, 0), (Vec3{10, 0, 0}));
    EXPECT_EQ(s.mesh.vertex(0, 1), (Vec3{12, 0, 0}));
    EXPECT_EQ(s.mesh.vertex(0, 2), (Vec3{10, 2, 0}));
    // An absolute path works too.
    const std::string abs = (fs::path(tmp.dir()) / "tri.obj").string();
    const Scene a = load_scene(tmp.file("abs.json", shapes(R"({"type": "mesh", "file": ")" + abs + "\"}")));
    EXPECT_EQ(a.mesh.triangle_count(), 1u);
}

TEST(JsonScene, TriangleOnlySceneIsTheMeshItself) {
    TempDir tmp;
    const Scene json = load_scene(tmp.file("scene.json", shapes(R"({"type": "mesh", "file": "meshes/quad.obj"})")));
    const Scene obj = load_scene(tmp.dir() + "/meshes/quad.obj");
    EXPECT_FALSE(json.has_shapes());
    EXPECT_EQ(json.fingerprint(), obj.fingerprint());
    // The Triangles fast path: 36 bytes per primitive, no id table.
    EXPECT_EQ(build_accel("bvh", json)->stats().primitive_bytes, 2u * 36u);
}

TEST(JsonScene, EmptyAndReservedKeys) {
    TempDir tmp;
    const Scene empty = load_scene(tmp.file("e.json", R"({"shapes": []})"));
    EXPECT_EQ(empty.primitive_count(), 0u);
    EXPECT_TRUE(empty.bounds().empty());
    const Scene reserved = load_scene(tmp.file(
        "r.json", R"({"camera": {"anything": 1}, "materials": [1, 2], "lights": null, "shapes": [)" +
                      std::string(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "red"})") +
                      "]}"));
    EXPECT_EQ(reserved.primitive_count(), 1u);
}

TEST(JsonScene, FingerprintCoversShapesAndOrder) {
    TempDir tmp;
    const uint64_t a = load_scene(tmp.file("a.json", shapes(std::string(kSphere) + ", " + kTorus))).fingerprint();
    const uint64_t b = load_scene(tmp.file("b.json", shapes(std::string(kTorus) + ", " + kSphere))).fingerprint();
    const uint64_t c = load_scene(tmp.file("c.json", shapes(R"({"type": "sphere", "center": [0, 0, 10], "radius": 1.0001}, )" +
                                                            std::string(kTorus))))
                           .fingerprint();
    const uint64_t a2 = load_scene(tmp.file("a2.json", shapes(std::string(kSphere) + ", " + kTorus))).fingerprint();
    EXPECT_EQ(a, a2);
    EXPECT_NE(a, b);
    EXPECT_NE(a, c);
}

TEST(JsonScene, SavedStructureIsBoundToTheShapes) {
    TempDir tmp;
    const Scene s = load_scene(tmp.file("s.json", shapes(std::string(kSphere) + ", " + kTorus)));
    const auto bvh = build_accel("bvh", s);
    const std::string saved = tmp.dir() + "/s.bvh";
    save_accel(*bvh, s, saved);
    const auto loaded = load_accel(saved, s);
    const Ray r{{0, 0, 20}, 0.0f, {0, 0, -1}, kInfinity};
    EXPECT_EQ(loaded->intersect(r).t, bvh->intersect(r).t);
    const Scene other = load_scene(tmp.file("o.json", shapes(R"({"type": "sphere", "center": [0, 0, 10], "radius": 2}, )" +
                                                             std::string(kTorus))));
    EXPECT_THROW(load_accel(saved, other), Error);
}

TEST(JsonScene, DocumentErrors) {
    TempDir tmp;
    expect_error(tmp, "{\"shapes\": [\n  {\"type\": \"sphere\",, }]}", {"invalid JSON", "line 2"});
    expect_error(tmp, "[1, 2]", {"must be an object"});
    expect_error(tmp, R"({"shape": []})", {"unknown top-level key 'shape'", "'shapes'", "camera"});
    expect_error(tmp, R"({"camera": {}})", {"missing top-level key 'shapes'"});
    expect_error(tmp, R"({"shapes": {}})", {"'shapes' must be an array"});
    expect_error(tmp, R"({"shapes": [], "shapes": []})", {"top-level key 'shapes' given twice"});
    expect_error(tmp, R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1e400}]})", {"invalid JSON", "1e400"});
}

TEST(JsonScene, ShapeErrorsNameShapeAndField) {
    TempDir tmp;
    auto bad = [&](const std::string& shape, const std::vector<std::string>& fragments) {
        SCOPED_TRACE(shape);
        expect_error(tmp, shapes(std::string(kSphere) + ", " + shape), fragments);
    };
    // Shape-level problems: shape 1 (after the good sphere).
    bad("3", {"shape 1", "must be an object"});
    bad(R"({"center": [0, 0, 0]})", {"shape 1", "missing field 'type'", "sphere", "torus", "mesh"});
    bad(R"({"type": 7})", {"shape 1", "field 'type' must be a string"});
    bad(R"({"type": "cube"})", {"shape 1", "unknown type 'cube'", "mesh, sphere, torus"});
    bad(R"({"type": "sphere", "center": [0,0,0], "radius": 1, "radius": 2})", {"shape 1", "field 'radius' given twice"});
    // Fields.
    bad(R"({"type": "sphere", "center": [0,0,0], "radius": 1, "colour": 1})",
        {"shape 1 (sphere)", "field 'colour'", "unknown field", "'center'", "'radius'"});
    bad(R"({"type": "sphere", "center": [0,0,0], "radiu": 1})", {"shape 1 (sphere)", "field 'radius'", "missing", "radiu"});
    bad(R"({"type": "sphere", "center": [0,0], "radius": 1})", {"shape 1 (sphere)", "field 'center'", "array of 3", "of 2"});
    bad(R"({"type": "sphere", "center": 5, "radius": 1})", {"shape 1 (sphere)", "field 'center'", "array of 3"});
    bad(R"({"type": "sphere", "center": [0,"a",0], "radius": 1})", {"shape 1 (sphere)", "field 'center'", "element 1", "a string"});
    bad(R"({"type": "sphere", "center": [0,0,0], "radius": -1})", {"shape 1 (sphere)", "field 'radius'", "positive", "-1"});
    bad(R"({"type": "sphere", "center": [0,0,0], "radius": 0})", {"shape 1 (sphere)", "field 'radius'", "positive"});
    bad(R"({"type": "sphere", "center": [0,0,0], "radius": 1e-50})", {"shape 1 (sphere)", "field 'radius'", "positive"});
    bad(R"({"type": "sphere", "center": [0,0,0], "radius": true})", {"shape 1 (sphere)", "field 'radius'", "a boolean"});
    bad(R"({"type": "sphere", "center": [0,0,0], "radius": "1"})", {"shape 1 (sphere)", "field 'radius'", "a string"});
    bad(R"({"type": "sphere", "center": [1e39,0,0], "radius": 1})", {"shape 1 (sphere)", "field 'center'", "float range"});
    bad(R"({"type": "sphere", "center": [3e38,0,0], "radius": 1e38})", {"shape 1 (sphere)", "bounds exceed the float range"});
    bad(R"({"type": "torus", "center": [0,0,0], "axis": [0,0,0], "major_radius": 1, "minor_radius": 0.5})",
        {"shape 1 (torus)", "field 'axis'", "non-zero"});
    bad(R"({"type": "torus", "center": [0,0,0], "axis": [0,1,0], "major_radius": 1, "minor_radius": 1})",
        {"shape 1 (torus)", "field 'minor_radius'", "less than major_radius"});
    bad(R"({"type": "torus", "center": [0,0,0], "axis": [0,1,0], "major_radius": -1, "minor_radius": 0.5})",
        {"shape 1 (torus)", "field 'major_radius'", "positive"});
    bad(R"({"type": "torus", "center": [0,0,0], "axis": [0,1,0], "major_radius": 1})",
        {"shape 1 (torus)", "field 'minor_radius'", "missing"});
    // Meshes.
    bad(R"({"type": "mesh"})", {"shape 1 (mesh)", "field 'file'", "missing"});
    bad(R"({"type": "mesh", "file": 3})", {"shape 1 (mesh)", "field 'file'", "string"});
    bad(R"({"type": "mesh", "file": "nope.ply"})", {"shape 1 (mesh)", "field 'file'", "no such file", "nope.ply"});
    bad(R"({"type": "mesh", "file": "scene.json"})", {"shape 1 (mesh)", "field 'file'", "unknown mesh format '.json'"});
    tmp.file("broken.obj", "v 0 0 0\nf 1 2 3\n");
    bad(R"({"type": "mesh", "file": "broken.obj"})", {"shape 1 (mesh)", "field 'file'", "broken.obj"});
    bad(R"({"type": "mesh", "file": "tri.obj", "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0]})",
        {"shape 1 (mesh)", "field 'transform'", "array of 16", "of 12"});
    bad(R"({"type": "mesh", "file": "tri.obj", "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]})",
        {"shape 1 (mesh)", "field 'transform'", "0 0 0 1"});
    bad(R"({"type": "mesh", "file": "tri.obj", "transform": [1,0,0,0, 0,1,0,0, 1,1,0,0, 0,0,0,1]})",
        {"shape 1 (mesh)", "field 'transform'", "singular"});
    bad(R"({"type": "mesh", "file": "tri.obj", "transform": [1,0,0,0, 0,1,0,0, 0,0,1e-12,0, 0,0,0,1]})",
        {"shape 1 (mesh)", "field 'transform'", "singular"});
    bad(R"({"type": "mesh", "file": "tri.obj", "transform": [1,0,0,0, 0,1,0,0, 0,0,null,0, 0,0,0,1]})",
        {"shape 1 (mesh)", "field 'transform'", "element 10", "null"});
    bad(R"({"type": "mesh", "file": "tri.obj", "transform": [1e38,0,0,0, 0,1e38,0,0, 0,0,1e38,0, 0,0,0,1]})",
        {"shape 1 (mesh)", "field 'transform'", "float range"});
    bad(R"({"type": "mesh", "file": "tri.obj", "transfrom": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]})",
        {"shape 1 (mesh)", "field 'transfrom'", "unknown field", "'transform'"});
}

// Issue 16: N shapes loaded in O(N^2) (nlohmann's callback parser rescans the shapes array at
// the end of every object): 200,000 spheres took 7 s. Counted, not timed: eight times the spheres
// must allocate at most 10 times the blocks and bytes (linear growth gives 8; an exact reserve or
// a copy per shape, 64). The same input always allocates the same, whatever the machine's load.
// (The old rescan itself allocated nothing: this guards the loader's own growth, and the shape
// count.)
TEST(JsonScene, ManySpheresLoadInLinearWork) {
    TempDir tmp;
    auto allocations_for = [&](size_t n) {
        std::string list;
        for (size_t i = 0; i < n; ++i)
            list += (i ? "," : "") + std::string(R"({"type": "sphere", "center": [)") + std::to_string(i) +
                    R"(, 0, 0], "radius": 0.25})";
        const std::string path = tmp.file("many.json", shapes(list));
        size_t loaded = 0;
        const test::Allocations a = test::count_allocations([&] { loaded = load_scene(path).shapes.size(); });
        EXPECT_EQ(loaded, n);
        return a;
    };
    const test::Allocations small = allocations_for(2500), large = allocations_for(20000);
    EXPECT_LT(large.blocks, 10 * small.blocks) << "2,500 spheres: " << small.blocks << " blocks, 20,000: " << large.blocks;
    EXPECT_LT(large.bytes, 10 * small.bytes) << "2,500 spheres: " << small.bytes << " bytes, 20,000: " << large.bytes;
    // Duplicate keys are still refused, naming the shape.
    expect_error(tmp, shapes(std::string(kSphere) + R"(, {"type": "sphere", "radius": 1, "radius": 2, "center": [0, 0, 0]})"),
                 {"shape 1: field 'radius' given twice"});
}

}  // namespace
}  // namespace thicket::json_scene_test
