// glTF instancing (load_gltf_scene): a mesh that several nodes place is one geometry with an
// instance per node, its world transform composed through the node hierarchy; the instanced scene
// answers rays as the flattened one (LoadOptions::flatten) does, materials included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "loader_test_util.h"
#include "support/gltf_instances_scene.h"
#include "thicket/accel/registry.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::gltf_instances_test {
namespace {

using loader_test::TempDir;

/// Writes the shared scene (with `extra_nodes`) and its buffer into `tmp`; returns the .gltf path.
std::string write_scene(const TempDir& tmp, const std::vector<std::string>& extra_nodes = {}) {
    tmp.file("scene.bin", testing::gltf_instances_buffer());
    return tmp.file("scene.gltf", testing::gltf_instances_json("scene.bin", extra_nodes));
}

LoadOptions flattened() {
    LoadOptions o;
    o.flatten = true;
    return o;
}

/// The material name of the hit's triangle: through its prototype in a scene with instances.
std::string material_of(const Scene& scene, const Ray& ray, const Hit& hit) {
    uint32_t prim = hit.prim;
    if (!scene.instances.empty()) {
        InstancePlace place;
        if (!place_instanced_hit(scene, ray, hit, place)) return "(no place)";
        prim = place.hit.prim;
    }
    if (prim >= scene.mesh.material_ids.size()) return "(no material id)";
    const uint32_t id = scene.mesh.material_ids[prim];
    return id < scene.mesh.materials.size() ? scene.mesh.materials[id].name : "(bad material id)";
}

/// A float in [0, 1) from the generator's top 24 bits: the same on every standard library.
float unit(std::mt19937& rng) { return float(rng() >> 8) * (1.0f / 16777216.0f); }

/// Brute force over both scenes, `count` rays from a sphere around the flattened scene's bounds
/// towards points inside them: the same hit or miss, the same t within a relative 1e-4 (the
/// instanced ray is transformed, the flattened triangles were: the roundings differ) and the same
/// material. Returns how many rays hit.
size_t expect_same_answers(const Scene& instanced, const Scene& flat, size_t count) {
    const std::unique_ptr<Accel> a = build_accel("brute", instanced, 1), b = build_accel("brute", flat, 1);
    const Aabb box = flat.bounds();
    const Vec3 centre = (box.min + box.max) * 0.5f, extent = box.max - box.min;
    const float radius = length(extent);
    std::mt19937 rng(27);
    size_t hits = 0;
    for (size_t i = 0; i < count; ++i) {
        const float z = 2.0f * unit(rng) - 1.0f, phi = 6.2831853f * unit(rng), s = std::sqrt(1.0f - z * z);
        Ray ray;
        ray.org = centre + Vec3{s * std::cos(phi), s * std::sin(phi), z} * radius;
        const Vec3 target = box.min + Vec3{unit(rng) * extent.x, unit(rng) * extent.y, unit(rng) * extent.z};
        ray.dir = target - ray.org;
        const Hit hi = a->intersect(ray), hf = b->intersect(ray);
        if (hi.found() != hf.found()) {
            ADD_FAILURE() << "ray " << i << ": instanced t " << hi.t << ", flattened t " << hf.t;
            continue;
        }
        if (!hf.found()) continue;
        ++hits;
        EXPECT_NEAR(hi.t, hf.t, 1e-4f * std::max(1.0f, hf.t)) << "ray " << i;
        EXPECT_EQ(material_of(instanced, ray, hi), material_of(flat, ray, hf)) << "ray " << i;
    }
    return hits;
}

TEST(GltfInstances, SharedMeshIsOneGeometryWithAnInstancePerNode) {
    TempDir tmp;
    const std::string path = write_scene(tmp);
    const Scene instanced = load_scene(path), flat = load_scene(path, flattened());
    // Geometry 0: the ground (placed once, flattened) under instance 0; geometry 1: mesh 0, held
    // once (a tetrahedron and a square), placed by nodes 1, 2 and 3.
    EXPECT_EQ(instanced.geometry_count(), 2u);
    ASSERT_EQ(instanced.instances.size(), 4u);
    EXPECT_EQ(instanced.instances[0].geometry, 0u);
    for (size_t i = 1; i < 4; ++i) EXPECT_EQ(instanced.instances[i].geometry, 1u) << i;
    EXPECT_EQ(instanced.mesh.triangle_count(), 2u + 6u);
    EXPECT_EQ(instanced.instanced_primitive_count(), 2u + 3u * 6u);
    EXPECT_TRUE(flat.instances.empty());
    EXPECT_EQ(flat.mesh.triangle_count(), 2u + 3u * 6u);
    // --flatten is the loader as it always was.
    const TriangleMesh before = load_gltf(path);
    EXPECT_EQ(flat.mesh.positions, before.positions);
    EXPECT_EQ(flat.mesh.indices, before.indices);
    EXPECT_EQ(flat.mesh.material_ids, before.material_ids);

    // The world transforms, worked out by hand: node 1 is parent * T(0, 1, 0) and node 2 parent *
    // T(1, 0, 2) R(120 degrees about (1, 1, 1)) S(0.5), the parent T(3, 0, 0) Rz(45 degrees)
    // S(1, 2, 1); node 3's column-major matrix mirrors x, shears z into y and moves by -3 in x.
    // Brute force alone cannot see these: the flattened scene goes through the same hierarchy.
    const float h = std::sqrt(0.5f);
    auto expect_near = [](Vec3 got, Vec3 want, const char* what) {
        EXPECT_NEAR(got.x, want.x, 1e-5f) << what;
        EXPECT_NEAR(got.y, want.y, 1e-5f) << what;
        EXPECT_NEAR(got.z, want.z, 1e-5f) << what;
    };
    expect_near(instanced.instances[1].transform.point({1, 0, 0}), {3 - h, 3 * h, 0}, "node 1");
    expect_near(instanced.instances[2].transform.point({1, 0, 0}), {3, 2 * h, 2}, "node 2");
    expect_near(instanced.instances[3].transform.point({0, 0, 1}), {-3, 0.3f, 1}, "node 3");
    expect_near(instanced.instances[3].transform.point({1, 0, 0}), {-4, 0, 0}, "node 3");

    const size_t hits = expect_same_answers(instanced, flat, 400);
    EXPECT_GT(hits, 100u) << "too few rays hit for the comparison to mean much";
}

TEST(GltfInstances, AMeshPlacedOnceLeavesTheSceneFlat) {
    TempDir tmp;
    tmp.file("scene.bin", testing::gltf_instances_buffer());
    // Only node 4 (the ground) and a root placing mesh 0 once.
    std::string json = testing::gltf_instances_json("scene.bin");
    json.replace(json.find("\"nodes\": [0, 3, 4]"), 18, "\"nodes\": [1, 4]");
    const Scene s = load_scene(tmp.file("once.gltf", json));
    EXPECT_TRUE(s.instances.empty());
    EXPECT_EQ(s.mesh.triangle_count(), 2u + 6u);
}

// A node whose transform instancing refuses (scale 0 in z: singular) is flattened with the meshes
// placed once; the others of its mesh stay instances, and the answers stay the flattened scene's.
TEST(GltfInstances, ASingularNodeIsFlattenedInstead) {
    TempDir tmp;
    const std::string path = write_scene(tmp, {R"({"mesh": 0, "translation": [0, 3, 0], "scale": [2, 2, 0]})"});
    const Scene instanced = load_scene(path), flat = load_scene(path, flattened());
    EXPECT_EQ(instanced.instances.size(), 4u);
    EXPECT_EQ(instanced.geometry(0).count, 2u + 6u);  // the ground and the flattened node
    EXPECT_EQ(instanced.instanced_primitive_count(), flat.mesh.triangle_count());
    expect_same_answers(instanced, flat, 200);
}

}  // namespace
}  // namespace thicket::gltf_instances_test
