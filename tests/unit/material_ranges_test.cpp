// The material parameter table (thicket/scene/material_ranges.h) and its three readers: MTL (through
// the OBJ loader), glTF and the JSON scene's `materials`. Every value the table refuses is refused
// by every format that can carry it, with the table's words after a location that names the file
// and line or the JSON path; glTF factors of the wrong JSON type or length are errors too.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "support/temp_dir.h"
#include "thicket/core/error.h"
#include "thicket/render/render_json.h"
#include "thicket/render/render_scene.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/material_ranges.h"
#include "thicket/scene/scene.h"

namespace thicket::material_ranges_test {
namespace {

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/// Small files in each format around one material, and the error each load gives ("" if none).
class Formats {
public:
    std::string mtl_path() const { return dir_.dir() + "/m.mtl"; }
    std::string obj_path() const { return dir_.dir() + "/t.obj"; }
    std::string json_path() const { return dir_.dir() + "/s.json"; }
    std::string gltf_path() const { return dir_.dir() + "/t.gltf"; }

    /// An OBJ triangle whose material m has the MTL statement `line` (on line 2 of m.mtl).
    std::string mtl_error(const std::string& line) const {
        dir_.file("m.mtl", "newmtl m\n" + line + "\n");
        dir_.file("t.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
        return error_of([&] { load_obj(obj_path()); });
    }
    /// A JSON scene whose material m has the fields `fields`, applied for the renderer.
    std::string json_error(const std::string& fields) const {
        dir_.file("s.json", R"({"materials": {"m": {)" + fields +
                                R"(}}, "shapes": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})");
        return error_of([&] {
            const Scene scene = load_scene(json_path());
            RenderScene rs = make_render_scene(scene);
            apply_json_render_settings(json_path(), rs);
        });
    }
    /// A glTF triangle whose one material is the JSON object `material`.
    std::string gltf_error(const std::string& material) const { return error_of([&] { load_gltf(write_gltf(material)); }); }
    std::string write_gltf(const std::string& material) const {
        std::string bin;
        for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) bin.append(reinterpret_cast<const char*>(&v), 4);
        dir_.file("t.bin", bin);
        return dir_.file("t.gltf", R"({"asset": {"version": "2.0"}, "nodes": [{"mesh": 0}],
          "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
          "materials": [)" + material + R"(],
          "buffers": [{"uri": "t.bin", "byteLength": 36}],
          "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
          "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}]})");
    }

private:
    testing::TempDir dir_{"thicket_material_ranges"};
};

TEST(MaterialRanges, TableRefusesOutsideAndAcceptsItsEnds) {
    const auto table = material_ranges();
    ASSERT_EQ(table.size(), size_t(MaterialParam::Roughness) + 1);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < table.size(); ++i) {
        const MaterialRange& r = table[i];
        EXPECT_EQ(size_t(r.param), i);
        EXPECT_EQ(&material_range(r.param), &r);
        EXPECT_TRUE(std::isfinite(r.lo) && std::isfinite(r.hi) && r.lo <= r.hi) << r.what;
        EXPECT_TRUE(*r.mtl || *r.json || *r.gltf) << r.what << " is read by no format";
        EXPECT_EQ(material_value_problem(r.param, r.lo), "") << r.what;
        EXPECT_EQ(material_value_problem(r.param, r.hi), "") << r.what;
        for (double bad : {nan, inf, -inf, r.lo - 0.5, r.hi + 0.5, r.hi * 2 + 1, 1e20, -1e20})
            EXPECT_NE(material_value_problem(r.param, bad), "") << r.what << " accepted " << bad;
    }
    EXPECT_NE(material_value_problem(MaterialParam::Illum, 3.5), "");
    EXPECT_EQ(material_value_problem(MaterialParam::Illum, 3.0), "");
    EXPECT_EQ(material_value_problem(MaterialParam::Emission, 1e39),
              "must be a number from 0 to 1e+06 (emitted radiance), got 1e+39");
    EXPECT_EQ(material_value_problem(MaterialParam::Ior, 0.5), "") << "ior < 1: an optically thinner inside";
    // A Material made in code is judged by the same table; illum -1 means "none given".
    Material m;
    EXPECT_EQ(material_problem(m), "");
    m.emission = {1.0f, float(inf), 0.0f};
    EXPECT_EQ(material_problem(m), "Ke[1]: " + material_value_problem(MaterialParam::Emission, inf));
    m = Material{};
    m.illum = 11;
    EXPECT_EQ(material_problem(m), "illum: " + material_value_problem(MaterialParam::Illum, 11));
}

// One table entry, one bad value, three formats: the same words after each format's location.
TEST(MaterialRanges, EveryReaderRefusesTheSameValueTheSameWay) {
    struct Case {
        MaterialParam param;
        double value;
        const char* mtl;     // the MTL line ("" when MTL cannot say it)
        const char* mtl_at;
        const char* json;    // the JSON material's fields
        const char* json_at;
        const char* gltf;    // the glTF material object
        const char* gltf_at;
    };
    const Case cases[] = {
        {MaterialParam::Emission, 1e39, "Ke 1e39 1 1", "Ke[0]", R"("ke": [1e39, 1, 1])", "materials.m.ke[0]",
         R"({"emissiveFactor": [1e39, 1, 1]})", "materials[0].emissiveFactor[0]"},
        {MaterialParam::Emission, -1, "Ke 0 0 -1", "Ke[2]", R"("ke": [0, 0, -1])", "materials.m.ke[2]",
         R"({"emissiveFactor": [0, 0, -1]})", "materials[0].emissiveFactor[2]"},
        {MaterialParam::Emission, 2e6, "Ke 2e6", "Ke", R"("ke": 2e6)", "materials.m.ke",
         R"({"emissiveFactor": [2e6, 0, 0]})", "materials[0].emissiveFactor[0]"},
        {MaterialParam::Diffuse, 2, "Kd 0.5 2 0.5", "Kd[1]", R"("kd": [0.5, 2, 0.5])", "materials.m.kd[1]",
         R"({"pbrMetallicRoughness": {"baseColorFactor": [0.5, 2, 0.5, 1]}})",
         "materials[0].pbrMetallicRoughness.baseColorFactor[1]"},
        {MaterialParam::Diffuse, -0.5, "Kd -0.5", "Kd", R"("kd": -0.5)", "materials.m.kd",
         R"({"pbrMetallicRoughness": {"baseColorFactor": [-0.5, 0, 0, 1]}})",
         "materials[0].pbrMetallicRoughness.baseColorFactor[0]"},
        {MaterialParam::Specular, 1.5, "Ks 1.5", "Ks", R"("ks": 1.5)", "materials.m.ks", "", ""},
        {MaterialParam::Ior, 0, "Ni 0", "Ni", R"("ni": 0)", "materials.m.ni",
         R"({"extensions": {"KHR_materials_ior": {"ior": 0}}})", "materials[0].extensions.KHR_materials_ior.ior"},
        {MaterialParam::Ior, -1.5, "Ni -1.5", "Ni", R"("ni": -1.5)", "materials.m.ni",
         R"({"extensions": {"KHR_materials_ior": {"ior": -1.5}}})", "materials[0].extensions.KHR_materials_ior.ior"},
        {MaterialParam::Ior, 1e39, "Ni 1e39", "Ni", R"("ni": 1e39)", "materials.m.ni",
         R"({"extensions": {"KHR_materials_ior": {"ior": 1e39}}})", "materials[0].extensions.KHR_materials_ior.ior"},
        {MaterialParam::Dissolve, 2, "d 2", "d", R"("d": 2)", "materials.m.d",
         R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 2]}})",
         "materials[0].pbrMetallicRoughness.baseColorFactor[3]"},
        {MaterialParam::Dissolve, -1, "d -1", "d", R"("d": -1)", "materials.m.d", "", ""},
        {MaterialParam::Transparency, 2, "Tr 2", "Tr", "", "",
         R"({"extensions": {"KHR_materials_transmission": {"transmissionFactor": 2}}})",
         "materials[0].extensions.KHR_materials_transmission.transmissionFactor"},
        {MaterialParam::Shininess, -10, "Ns -10", "Ns", R"("ns": -10)", "materials.m.ns", "", ""},
        {MaterialParam::Illum, 99, "illum 99", "illum", R"("illum": 99)", "materials.m.illum", "", ""},
        {MaterialParam::Illum, -3, "illum -3", "illum", R"("illum": -3)", "materials.m.illum", "", ""},
        {MaterialParam::Illum, 3.5, "illum 3.5", "illum", R"("illum": 3.5)", "materials.m.illum", "", ""},
        {MaterialParam::Illum, 1e20, "illum 1e20", "illum", R"("illum": 1e20)", "materials.m.illum", "", ""},
        {MaterialParam::EmissiveStrength, 1e39, "", "", "", "",
         R"({"emissiveFactor": [1, 1, 1], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e39}}})",
         "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength"},
        {MaterialParam::Metallic, 1.5, "", "", "", "", R"({"pbrMetallicRoughness": {"metallicFactor": 1.5}})",
         "materials[0].pbrMetallicRoughness.metallicFactor"},
        {MaterialParam::Roughness, -0.5, "", "", "", "", R"({"pbrMetallicRoughness": {"roughnessFactor": -0.5}})",
         "materials[0].pbrMetallicRoughness.roughnessFactor"},
    };
    const Formats f;
    for (const Case& c : cases) {
        const std::string problem = material_value_problem(c.param, c.value);
        ASSERT_NE(problem, "") << c.mtl << c.gltf;
        if (*c.mtl) {
            const std::string e = f.mtl_error(c.mtl);
            EXPECT_EQ(e.rfind(f.obj_path() + ": line 1: mtllib: " + f.mtl_path() + ": line 2: ", 0), 0u) << e;
            EXPECT_TRUE(ends_with(e, std::string(c.mtl_at) + ": " + problem)) << c.mtl << " -> " << e;
        }
        if (*c.json) {
            const std::string e = f.json_error(c.json);
            EXPECT_EQ(e, f.json_path() + ": " + c.json_at + ": " + problem) << c.json;
        }
        if (*c.gltf) {
            const std::string e = f.gltf_error(c.gltf);
            EXPECT_EQ(e, f.gltf_path() + ": " + c.gltf_at + ": " + problem) << c.gltf;
        }
    }
}

// What JSON cannot spell (NaN, infinity) MTL can: refused with the table's words, never
// converted (a float beyond its range, an int out of range was undefined behaviour).
TEST(MaterialRanges, MtlNonFiniteValuesAreRefused) {
    const Formats f;
    for (const char* line : {"Ke inf 1 1", "Ke 1e40", "Kd nan", "Ks -inf", "Ns nan", "Ni nan", "Ni inf", "Ni 0",
                             "d nan", "Tr inf", "illum nan", "illum inf", "illum 1e400"}) {
        const std::string e = f.mtl_error(line);
        EXPECT_NE(e.find(f.mtl_path() + ": line 2: "), std::string::npos) << line << " -> " << e;
        EXPECT_NE(e.find("must be a"), std::string::npos) << line << " -> " << e;
    }
    // JSON numbers beyond double are infinite after parsing: refused in the same words.
    const std::string e = f.json_error(R"("ke": [1e400, 0, 0])");
    EXPECT_TRUE(e.find("materials.m.ke[0]: ") != std::string::npos || e.find("invalid JSON") != std::string::npos) << e;
}

TEST(MaterialRanges, ValuesInsideTheRangesLoadAsWritten) {
    const Formats f;
    ASSERT_EQ(f.mtl_error("Ke 1e6 0 0.5\nKd 1 0 0\nNi 0.5\nd 0\nillum 7.0\nNs 1e6"), "");
    const TriangleMesh m = load_obj(f.obj_path());
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_EQ(m.materials[0].emission, Vec3(1e6f, 0.0f, 0.5f));
    EXPECT_FLOAT_EQ(m.materials[0].ior, 0.5f);
    EXPECT_EQ(m.materials[0].illum, 7);
    EXPECT_EQ(f.json_error(R"("ke": [1e6, 0, 0.5], "ni": 10, "d": 1, "illum": 10, "ns": 0)"), "");
    const TriangleMesh g = load_gltf(f.write_gltf(
        R"({"emissiveFactor": [1, 0.5, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e6}}})"));
    ASSERT_EQ(g.materials.size(), 1u);
    EXPECT_EQ(g.materials[0].emission, Vec3(1e6f, 5e5f, 0.0f));
    // A factor within its range times a strength within its range may still exceed the bound.
    const std::string e = f.gltf_error(
        R"({"emissiveFactor": [2, 0, 0], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 1e6}}})");
    EXPECT_EQ(e, f.gltf_path() + ": materials[0].emissiveFactor[0] x materials[0].extensions." +
                     "KHR_materials_emissive_strength.emissiveStrength: " +
                     material_value_problem(MaterialParam::Emission, 2e6));
}

// tinygltf replaced these by the defaults without a word.
TEST(MaterialRanges, GltfFactorsOfTheWrongTypeOrLengthAreErrors) {
    const Formats f;
    struct Case {
        const char* material;
        const char* expected;  // after "<file>: "
    };
    const Case cases[] = {
        {R"({"pbrMetallicRoughness": {"baseColorFactor": "red"}})",
         R"(materials[0].pbrMetallicRoughness.baseColorFactor: must be an array of 4 numbers, got "red")"},
        {R"({"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1]}})",
         "materials[0].pbrMetallicRoughness.baseColorFactor: must be an array of 4 numbers, got [1,1,1]"},
        {R"({"pbrMetallicRoughness": {"baseColorFactor": [1, "1", 1, 1]}})",
         R"(materials[0].pbrMetallicRoughness.baseColorFactor[1]: must be a number, got "1")"},
        {R"({"emissiveFactor": [1, 1]})", "materials[0].emissiveFactor: must be an array of 3 numbers, got [1,1]"},
        {R"({"emissiveFactor": [1, 1, 1, 1]})", "materials[0].emissiveFactor: must be an array of 3 numbers, got [1,1,1,1]"},
        {R"({"pbrMetallicRoughness": {"metallicFactor": "1"}})",
         R"(materials[0].pbrMetallicRoughness.metallicFactor: must be a number, got "1")"},
        {R"({"pbrMetallicRoughness": {"roughnessFactor": null}})",
         "materials[0].pbrMetallicRoughness.roughnessFactor: must be a number, got null"},
        {R"({"extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": true}}})",
         "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: must be a number, got true"},
        {R"({"extensions": {"KHR_materials_ior": {"ior": [1.5]}}})",
         "materials[0].extensions.KHR_materials_ior.ior: must be a number, got [1.5]"},
        {R"({"extensions": {"KHR_materials_ior": 1.5}})", "materials[0].extensions.KHR_materials_ior: must be an object, got 1.5"},
    };
    for (const Case& c : cases) {
        const std::string e = f.gltf_error(c.material);
        EXPECT_EQ(e, f.gltf_path() + ": " + c.expected) << c.material;
    }
}

// An mtllib whose file has no materials used to silence every "no such material" warning.
TEST(MaterialRanges, EmptyMaterialLibraryStillWarnsAboutUnknownMaterials) {
    const testing::TempDir dir("thicket_material_ranges");
    dir.file("empty.mtl", "# no materials here\n");
    const std::string obj = dir.file("t.obj", "mtllib empty.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    ::testing::internal::CaptureStderr();
    const TriangleMesh m = load_obj(obj);
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_NE(err.find("empty.mtl' has no materials"), std::string::npos) << err;
    EXPECT_NE(err.find("line 5: usemtl 'red': no such material"), std::string::npos) << err;
}

// The issue's emitter examples through a JSON `mesh` shape: the MTL's error reaches the user with
// the shape, the MTL file and its line.
TEST(MaterialRanges, JsonMeshShapeCarriesTheMtlError) {
    const Formats f;
    for (const char* line : {"Ke inf 1 1", "Ke 1e40 1 1"}) {
        ASSERT_NE(f.mtl_error(line), "");
        const testing::TempDir dir("thicket_material_ranges");
        const std::string json =
            dir.file("s.json", R"({"shapes": [{"type": "mesh", "file": ")" + f.obj_path() + R"("}]})");
        const std::string e = error_of([&] { load_scene(json); });
        EXPECT_NE(e.find("shape 0 (mesh): field 'file': "), std::string::npos) << e;
        EXPECT_NE(e.find(f.mtl_path() + ": line 2: Ke[0]: must be a number from 0 to 1e+06 (emitted radiance)"),
                  std::string::npos)
            << e;
    }
    const std::string e = f.gltf_error(R"({"emissiveFactor": [1e39, 1, 1]})");
    EXPECT_NE(e, "");
}

}  // namespace
}  // namespace thicket::material_ranges_test
