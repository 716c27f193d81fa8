// Double-precision scenes and entry points: PLY `double` vertices kept as given beside their
// float rounding, scenes that combine meshes with and without them, the precision option in the
// canonical spec, and float structures refusing double rays by naming the option.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "support/temp_dir.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/scene/scene.h"

namespace thicket::testing::double_precision_test {
namespace {

constexpr const char* kAsciiDoubleHeader =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(DoublePly, AsciiDoubleVerticesAreKept) {
    TempDir dir("thicket-double-ply");
    const std::string path = dir.file("far.ply", std::string(kAsciiDoubleHeader) +
                                                     "10000000.01 20000000.02 5.5\n10000000.03 20000000.02 5.5\n"
                                                     "10000000.01 20000000.05 5.5\n3 0 1 2\n");
    const Scene scene = load_scene(path);
    ASSERT_EQ(scene.mesh.positions_double.size(), 3u);
    EXPECT_EQ(scene.mesh.positions_double[1].x, 10000000.03);
    EXPECT_EQ(scene.mesh.positions_double[2].y, 20000000.05);
    // The float positions are the same points rounded: float structures keep working.
    EXPECT_EQ(scene.mesh.positions[1].x, float(10000000.03));
    EXPECT_EQ(scene.mesh.vertex_double(0, 1).x, 10000000.03);
}

TEST(DoublePly, BinaryMixedPropertiesKeepDoubles) {
    // x double, y float, z double, little-endian: any double coordinate keeps the vertex in double.
    std::string body;
    auto put = [&](const void* p, size_t n) { body.append(static_cast<const char*>(p), n); };
    const double xs[3] = {1e8 + 0.25, 1e8 + 0.5, 1e8 + 0.25};
    const float ys[3] = {0.0f, 0.0f, 1.0f};
    for (int i = 0; i < 3; ++i) {
        put(&xs[i], 8);
        put(&ys[i], 4);
        const double z = -3e7 - 0.125 * i;
        put(&z, 8);
    }
    const unsigned char n = 3;
    const int32_t face[3] = {0, 1, 2};
    put(&n, 1);
    put(face, 12);
    TempDir dir("thicket-double-ply");
    const std::string path = dir.file(
        "mixed.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty float y\n"
                     "property double z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" + body);
    const Scene scene = load_scene(path);
    ASSERT_EQ(scene.mesh.positions_double.size(), 3u);
    EXPECT_EQ(scene.mesh.positions_double[1].x, 1e8 + 0.5);
    EXPECT_EQ(scene.mesh.positions_double[2].z, -3e7 - 0.25);
    EXPECT_EQ(scene.mesh.positions_double[2].y, 1.0);
}

TEST(DoublePly, FloatFilesHaveNoDoubleCopy) {
    TempDir dir("thicket-double-ply");
    const std::string path = dir.file("near.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                  "property float y\nproperty float z\nelement face 1\nproperty list "
                                                  "uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_TRUE(load_scene(path).mesh.positions_double.empty());
}

TEST(DoubleScene, MeshesWithAndWithoutDoublesShareOneArray) {
    TriangleMesh plain;
    plain.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    plain.indices = {0, 1, 2};
    TriangleMesh far = plain;
    far.positions_double = {{1e7 + 0.01, 0, 0}, {1e7 + 1, 0, 0}, {1e7, 1, 0}};
    for (size_t i = 0; i < 3; ++i) far.positions[i] = far.positions_double[i].to_float();
    Scene scene;
    scene.add_mesh(plain);
    scene.add_mesh(far);
    scene.add_mesh(plain);
    ASSERT_EQ(scene.mesh.positions_double.size(), scene.mesh.positions.size());
    EXPECT_EQ(scene.mesh.vertex_double(0, 1).x, 1.0);
    EXPECT_EQ(scene.mesh.vertex_double(1, 0).x, 1e7 + 0.01);
    EXPECT_EQ(scene.mesh.vertex_double(2, 1).x, 1.0);
    // Moving a geometry's vertices (float) moves their double copies too.
    const Vec3 moved[3] = {{5, 5, 5}, {6, 5, 5}, {5, 6, 5}};
    scene.set_vertices(1, moved);
    EXPECT_EQ(scene.mesh.vertex_double(1, 1).x, 6.0);
}

TEST(DoubleSpec, CanonicalSpecShowsPrecision) {
    EXPECT_NE(parse_accel_spec("bvh:precision=double").str().find("precision=double"), std::string::npos);
    EXPECT_NE(parse_accel_spec("brute").str().find("precision=float"), std::string::npos);
    try {
        parse_accel_spec("bvh8:precision=double");
        ADD_FAILURE() << "bvh8 took precision=double";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("precision"), std::string::npos) << e.what();
    }
}

TEST(DoubleSpec, FloatStructuresRefuseDoubleBatches) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2};
    Scene scene;
    scene.add_mesh(mesh);
    const RayD rays[1] = {RayD{{0.2, 0.2, -1}, 0.0, {0, 0, 1}, 10.0}};
    HitD hits[1];
    for (const char* spec : {"brute", "bvh", "grid"}) {
        try {
            build_accel(spec, scene)->intersect_double(rays, hits);
            ADD_FAILURE() << spec << " traced double rays";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("precision=double"), std::string::npos) << e.what();
        }
    }
    build_accel("bvh:precision=double", scene)->intersect_double(rays, hits);
    EXPECT_EQ(hits[0].prim, 0u);
    EXPECT_DOUBLE_EQ(hits[0].t, 1.0);
    // Not saved (its boxes are double): refused the way every unsavable structure is.
    EXPECT_THROW(saved_accel_bytes(*build_accel("bvh:precision=double", scene), scene), Error);
}

}  // namespace
}  // namespace thicket::testing::double_precision_test
