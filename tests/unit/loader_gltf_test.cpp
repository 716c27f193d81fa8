// glTF loader tests: embedded and external buffers, GLB, node transforms, corrupt files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "allocation_counter.h"
#include "loader_test_util.h"
#include "thicket/core/error.h"
#include "thicket/render/bsdf.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::loader_gltf_test {
namespace {

using namespace loader_test;

// ---- glTF --------------------------------------------------------------------------------------

std::string base64(const std::string& bytes) {
    static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= uint8_t(bytes[i + 2]);
        out += alphabet[(v >> 18) & 63];
        out += alphabet[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? alphabet[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? alphabet[v & 63] : '=';
    }
    return out;
}

/// One triangle (indexed, ushort) plus 4 vertices used by a non-indexed strip and fan.
std::string gltf_buffer() {
    std::string b;
    auto f = [&](float v) { b.append(reinterpret_cast<const char*>(&v), 4); };
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) f(v);  // 0..36: triangle
    for (uint16_t i : {uint16_t(0), uint16_t(1), uint16_t(2), uint16_t(0)})
        b.append(reinterpret_cast<const char*>(&i), 2);
    // 44..92: quad corners
    for (float v : {0.f, 0.f, 5.f, 1.f, 0.f, 5.f, 0.f, 1.f, 5.f, 1.f, 1.f, 5.f}) f(v);
    return b;
}

std::string gltf_json(const std::string& buffer_uri, size_t length) {
    const std::string uri = buffer_uri.empty() ? "" : "\"uri\": \"" + buffer_uri + "\", ";
    return R"({"asset": {"version": "2.0"}, "scene": 0,
  "scenes": [{"nodes": [0, 2]}],
  "nodes": [{"translation": [10, 0, 0], "children": [1]},
            {"scale": [2, 2, 2], "mesh": 0},
            {"matrix": [0,1,0,0, -1,0,0,0, 0,0,1,0, 0,0,0,1], "mesh": 1}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]},
             {"primitives": [{"attributes": {"POSITION": 2}, "mode": 5},
                             {"attributes": {"POSITION": 2}, "mode": 6, "material": 1},
                             {"attributes": {"POSITION": 2}, "mode": 1}]}],
  "materials": [{"name": "orange", "pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.25, 1], "metallicFactor": 0},
                 "emissiveFactor": [2, 3, 4]},
                {"emissiveFactor": [1, 1, 1],
                 "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 5}}}],
  "buffers": [{)" +
           uri + R"("byteLength": )" + std::to_string(length) + R"(}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 6},
                  {"buffer": 0, "byteOffset": 44, "byteLength": 48, "byteStride": 12}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
                {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3"}]})";
}

std::string embedded_gltf() {
    const std::string b = gltf_buffer();
    return gltf_json("data:application/octet-stream;base64," + base64(b), b.size());
}

std::string make_glb(std::string json, std::string bin) {
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    std::string out;
    auto u32 = [&](uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
    u32(0x46546C67u);
    u32(2);
    u32(uint32_t(12 + 8 + json.size() + 8 + bin.size()));
    u32(uint32_t(json.size()));
    u32(0x4E4F534Au);
    out += json;
    u32(uint32_t(bin.size()));
    u32(0x004E4942u);
    out += bin;
    return out;
}

void expect_gltf_scene(const TriangleMesh& m) {
    ASSERT_EQ(m.triangle_count(), 5u);
    // Node 0 translates by (10,0,0); its child scales by 2: p -> 10 + 2p.
    EXPECT_EQ(m.vertex(0, 0), Vec3(10, 0, 0));
    EXPECT_EQ(m.vertex(0, 1), Vec3(12, 0, 0));
    EXPECT_EQ(m.vertex(0, 2), Vec3(10, 2, 0));
    // Node 2's matrix rotates 90 degrees about z: (x,y,z) -> (-y,x,z). Strip: (0,1,2), (1,3,2).
    EXPECT_EQ(m.vertex(1, 0), Vec3(0, 0, 5));
    EXPECT_EQ(m.vertex(1, 1), Vec3(0, 1, 5));
    EXPECT_EQ(m.vertex(2, 0), Vec3(0, 1, 5));
    EXPECT_EQ(m.vertex(2, 1), Vec3(-1, 1, 5));
    EXPECT_EQ(m.vertex(2, 2), Vec3(-1, 0, 5));
    // Fan: (0,1,2), (0,2,3).
    EXPECT_EQ(m.vertex(4, 0), Vec3(0, 0, 5));
    EXPECT_EQ(m.vertex(4, 2), Vec3(-1, 1, 5));
    ASSERT_EQ(m.materials.size(), 3u);
    EXPECT_EQ(m.materials[0].name, "orange");
    EXPECT_EQ(m.materials[0].diffuse, Vec3(1, 0.5f, 0.25f));
    EXPECT_EQ(m.materials[0].emission, Vec3(2, 3, 4));
    EXPECT_EQ(m.materials[1].emission, Vec3(5, 5, 5));
    EXPECT_EQ(m.materials[2].name, "default");
    const std::vector<uint32_t> ids = {0, 2, 2, 1, 1};
    EXPECT_EQ(m.material_ids, ids);
}

// glTF's metallic-roughness materials, mapped to the nearest of the path tracer's: a rough metal
// is glossy with its base colour as the specular colour, a smooth one a mirror, transmission glass
// (ior 1.5 by glTF's default), a non-metal Lambertian; the defaults (metallic 1) apply.
TEST(LoaderGltf, PbrMaterialsMapToTheNearestPathTracerMaterial) {
    TempDir tmp;
    const std::string b = gltf_buffer();
    const std::string json = R"({"asset": {"version": "2.0"}, "nodes": [{"mesh": 0}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}, {"attributes": {"POSITION": 0}, "material": 1},
                             {"attributes": {"POSITION": 0}, "material": 2}, {"attributes": {"POSITION": 0}, "material": 3},
                             {"attributes": {"POSITION": 0}, "material": 4}]}],
  "materials": [
    {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.2, 1], "roughnessFactor": 0.5}},
    {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 1, "roughnessFactor": 0}},
    {"pbrMetallicRoughness": {"metallicFactor": 0}, "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}}},
    {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0}},
    {"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.33}},
     "pbrMetallicRoughness": {"metallicFactor": 0}}],
  "buffers": [{"uri": "data:application/octet-stream;base64,)" + base64(b) + R"(", "byteLength": )" +
                             std::to_string(b.size()) + R"(}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}]})";
    const TriangleMesh m = load_gltf(tmp.file("pbr.gltf", json));
    ASSERT_EQ(m.materials.size(), 5u);
    // Rough gold: roughness 0.5, alpha 0.25, exponent 2 / 0.0625 - 2 = 30.
    EXPECT_EQ(m.materials[0].specular, Vec3(0.9f, 0.6f, 0.2f));
    EXPECT_EQ(m.materials[0].diffuse, Vec3(0.0f));
    EXPECT_FLOAT_EQ(m.materials[0].shininess, 30.0f);
    EXPECT_EQ(surface_from_material(m.materials[0]).kind, SurfaceKind::Glossy);
    EXPECT_EQ(surface_from_material(m.materials[1]).kind, SurfaceKind::Mirror);
    EXPECT_EQ(surface_from_material(m.materials[2]).kind, SurfaceKind::Dielectric);
    EXPECT_FLOAT_EQ(m.materials[2].ior, 1.5f);
    EXPECT_FLOAT_EQ(m.materials[2].dissolve, 0.0f);
    EXPECT_EQ(surface_from_material(m.materials[3]).kind, SurfaceKind::Lambert);
    EXPECT_EQ(m.materials[3].diffuse, Vec3(0.2f, 0.4f, 0.6f));
    EXPECT_FLOAT_EQ(m.materials[4].ior, 1.33f);
    // A transmission outside [0, 1] is an error that names the material.
    const std::string bad = std::string(json).replace(json.find("\"transmissionFactor\": 1}"), 24, "\"transmissionFactor\": 2}");
    try {
        load_gltf(tmp.file("bad.gltf", bad));
        ADD_FAILURE() << "accepted transmissionFactor 2";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("materials[2].extensions.KHR_materials_transmission.transmissionFactor: must be a number from 0 to 1"), std::string::npos) << e.what();
    }
}

TEST(LoaderGltf, EmbeddedBufferWithNodeTransforms) {
    TempDir tmp;
    expect_gltf_scene(load_gltf(tmp.file("scene.gltf", embedded_gltf())));
}

TEST(LoaderGltf, ExternalBufferAndGlb) {
    TempDir tmp;
    tmp.file("scene.bin", gltf_buffer());
    expect_gltf_scene(load_gltf(tmp.file("external.gltf", gltf_json("scene.bin", gltf_buffer().size()))));
    const std::string glb = make_glb(gltf_json("", gltf_buffer().size()), gltf_buffer());
    expect_gltf_scene(load_gltf(tmp.file("scene.glb", glb)));
    expect_gltf_scene(load_scene(tmp.file("UPPER.GLB", glb)).mesh);
    for (size_t len = 0; len < glb.size(); len += 3) {  // truncated containers fail cleanly
        const std::string path = tmp.file("cut" + std::to_string(len) + ".glb", glb.substr(0, len));
        EXPECT_THROW(load_gltf(path), Error) << len;
    }
}

TEST(LoaderGltf, TrsRotationIsApplied) {
    TempDir tmp;
    std::string json = embedded_gltf();
    const std::string from = R"({"scale": [2, 2, 2], "mesh": 0})";
    // 90 degrees about z, then scale (2,1,1) applied first: (1,0,0) -> (2,0,0) -> (0,2,0).
    json.replace(json.find(from), from.size(),
                 R"({"scale": [2, 1, 1], "rotation": [0, 0, 0.70710678, 0.70710678], "mesh": 0})");
    const TriangleMesh m = load_gltf(tmp.file("trs.gltf", json));
    const Vec3 p = m.vertex(0, 1);
    EXPECT_NEAR(p.x, 10.0f, 1e-5f);
    EXPECT_NEAR(p.y, 2.0f, 1e-5f);
    EXPECT_NEAR(p.z, 0.0f, 1e-5f);
}

TEST(LoaderGltf, CorruptFilesAreErrors) {
    TempDir tmp;
    const std::string good = embedded_gltf();
    auto variant = [&](const std::string& from, const std::string& to) {
        std::string s = good;
        const size_t at = s.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        if (at != std::string::npos) s.replace(at, from.size(), to);
        return s;
    };
    struct Case { std::string name, text; std::vector<std::string> fragments; };
    const std::vector<Case> cases = {
        {"json.gltf", good.substr(0, good.size() / 2), {}},
        {"count.gltf",
         variant(R"("count": 3, "type": "VEC3")", R"("count": 300, "type": "VEC3")"),
         {"accessor 0"}},
        {"offset.gltf",
         variant(R"("byteOffset": 36, "byteLength": 6)", R"("byteOffset": 36, "byteLength": 600)"),
         {}},
        {"stride.gltf", variant(R"("byteStride": 12)", R"("byteStride": 8)"), {"byteStride"}},
        {"index.gltf",
         variant(R"("bufferView": 1, "componentType": 5123, "count": 3)",
                 R"("bufferView": 1, "componentType": 5123, "count": 3, "byteOffset": 2)"),
         {}},
        {"cycle.gltf",
         variant(R"("scale": [2, 2, 2], "mesh": 0)", R"("scale": [2, 2, 2], "mesh": 0, "children": [0])"),
         {"node 0"}},
        {"mesh.gltf", variant(R"("mesh": 1})", R"("mesh": 7})"), {"mesh 7"}},
        {"material.gltf", variant(R"("material": 0)", R"("material": 9)"), {"material 9"}},
        {"ctype.gltf",
         variant(R"("componentType": 5126, "count": 3)", R"("componentType": 5121, "count": 3)"),
         {"POSITION"}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const std::string path = tmp.file(c.name, c.text);
        expect_error([&] { load_gltf(path); }, path, c.fragments);
    }
    // An index pointing past the vertices.
    std::string b = gltf_buffer();
    const uint16_t bad = 7;
    std::memcpy(&b[38], &bad, 2);
    const std::string range =
        tmp.file("range.gltf", gltf_json("data:application/octet-stream;base64," + base64(b), b.size()));
    expect_error([&] { load_gltf(range); }, range, {"index 7", "out of range"});
}

// ---- issue 16 ----------------------------------------------------------------------------------

TEST(LoaderGltf, ABufferUriThatIsADirectoryOrDeviceIsAnError) {
    TempDir tmp;
    for (const char* uri : {".", "/dev/zero", "missing.bin"}) {
        const std::string p = tmp.file("dir.gltf", gltf_json(uri, gltf_buffer().size()));
        try {
            load_gltf(p);
            ADD_FAILURE() << uri << ": no error";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind(p, 0), 0u) << what;
            EXPECT_EQ(what.find("bad_alloc"), std::string::npos) << what;
        } catch (const std::exception& e) {
            ADD_FAILURE() << uri << ": " << e.what();
        }
    }
}

/// A glTF file of one node whose `n` children each place the same one-triangle mesh, at x = i.
std::string nodes_sharing_a_mesh(size_t n) {
    std::string children, nodes;
    for (size_t i = 1; i <= n; ++i) {
        if (i > 1) children += ',';
        children += std::to_string(i);  // not "," + to_string(): GCC 12 warns falsely (-Wrestrict) on that
        nodes += ",{\"mesh\": 0, \"translation\": [" + std::to_string(i) + ", 0, 0]}";
    }
    const std::string b = gltf_buffer();
    return R"({"asset": {"version": "2.0"}, "nodes": [{"children": [)" + children + "]}" + nodes +
           R"(], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
  "buffers": [{"uri": "data:application/octet-stream;base64,)" + base64(b) + R"(", "byteLength": )" +
           std::to_string(b.size()) + R"(}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}]})";
}

// One node with N children sharing a mesh loaded in O(N^2) (an exact reserve per primitive):
// 10^6 children took over a minute. Counted, not timed: eight times the children must allocate at
// most 10 times the blocks and bytes (linear growth gives 8; the exact reserve per node, about 64).
TEST(LoaderGltf, ManyNodesSharingAMeshLoadInLinearWork) {
    TempDir tmp;
    auto allocations_for = [&](size_t n) {
        const std::string p = tmp.file("many.gltf", nodes_sharing_a_mesh(n));
        TriangleMesh m;
        const test::Allocations a = test::count_allocations([&] { m = load_gltf(p); });
        EXPECT_EQ(m.triangle_count(), n);
        EXPECT_EQ(m.vertex(n - 1, 1), Vec3(float(n) + 1, 0, 0));
        return a;
    };
    const test::Allocations small = allocations_for(5000), large = allocations_for(40000);
    EXPECT_LT(large.blocks, 10 * small.blocks) << "5,000 children: " << small.blocks << " blocks, 40,000: " << large.blocks;
    EXPECT_LT(large.bytes, 10 * small.bytes) << "5,000 children: " << small.bytes << " bytes, 40,000: " << large.bytes;
}

}  // namespace
}  // namespace thicket::loader_gltf_test
