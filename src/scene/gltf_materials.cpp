// glTF materials from the file's JSON (gltf_materials.h): every factor Thicket maps is checked for
// its JSON type and length and against the material table, and an error names its JSON path.
#include "gltf_materials.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include <nlohmann/json.hpp>

#include "thicket/core/error.h"
#include "thicket/scene/material_ranges.h"

namespace thicket::gltf {

namespace {

using nlohmann::json;

std::string shown(const json& v) {
    std::string s = v.dump();
    return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

class MaterialReader {
public:
    explicit MaterialReader(const std::string& path) : path_(path) {}

    [[noreturn]] void fail(const std::string& at, const std::string& what) const {
        throw Error(path_ + ": " + at + ": " + what);
    }

    /// The member `key` of object `parent` (at path `at`), or nullptr when absent; present but
    /// not an object when `object` is asked for is an error.
    const json* member(const json& parent, const char* key, const std::string& at, bool object) const {
        const auto it = parent.find(key);
        if (it == parent.end()) return nullptr;
        if (object && !it->is_object()) fail(at + "." + key, "must be an object, got " + shown(*it));
        return &*it;
    }

    /// A number the table accepts for `p`.
    double number(const json& v, const std::string& at, MaterialParam p) const {
        if (!v.is_number()) fail(at, "must be a number, got " + shown(v));
        const double x = v.get<double>();
        if (const std::string why = material_value_problem(p, x); !why.empty()) fail(at, why);
        return x;
    }

    /// An array of exactly `n` numbers, element i checked against params[i].
    std::vector<double> numbers(const json& v, const std::string& at, size_t n, const MaterialParam* params) const {
        if (!v.is_array() || v.size() != n)
            fail(at, "must be an array of " + std::to_string(n) + " numbers, got " + shown(v));
        std::vector<double> out(n);
        for (size_t i = 0; i < n; ++i) out[i] = number(v[i], at + "[" + std::to_string(i) + "]", params[i]);
        return out;
    }

    Material read(const json& m, size_t index) const {
        const std::string at = "materials[" + std::to_string(index) + "]";
        if (!m.is_object()) fail(at, "must be an object, got " + shown(m));
        Material out;
        out.name = "material" + std::to_string(index);
        if (const json* name = member(m, "name", at, false)) {
            if (!name->is_string()) fail(at + ".name", "must be a string, got " + shown(*name));
            if (!name->get<std::string>().empty()) out.name = name->get<std::string>();
        }
        // glTF's defaults: base colour 1, metallic 1, roughness 1, no emission, ior 1.5.
        std::vector<double> base = {1, 1, 1, 1};
        double metallic = 1.0, roughness = 1.0, strength = 1.0, transmission = 0.0, ior = 1.5;
        std::vector<double> emissive = {0, 0, 0};
        if (const json* pbr = member(m, "pbrMetallicRoughness", at, true)) {
            const std::string p = at + ".pbrMetallicRoughness";
            constexpr MaterialParam kBase[4] = {MaterialParam::Diffuse, MaterialParam::Diffuse, MaterialParam::Diffuse,
                                                MaterialParam::Dissolve};
            if (const json* f = member(*pbr, "baseColorFactor", p, false)) base = numbers(*f, p + ".baseColorFactor", 4, kBase);
            if (const json* f = member(*pbr, "metallicFactor", p, false))
                metallic = number(*f, p + ".metallicFactor", MaterialParam::Metallic);
            if (const json* f = member(*pbr, "roughnessFactor", p, false))
                roughness = number(*f, p + ".roughnessFactor", MaterialParam::Roughness);
        }
        constexpr MaterialParam kEmission[3] = {MaterialParam::Emission, MaterialParam::Emission, MaterialParam::Emission};
        if (const json* f = member(m, "emissiveFactor", at, false)) emissive = numbers(*f, at + ".emissiveFactor", 3, kEmission);
        const std::string strength_at = at + ".extensions.KHR_materials_emissive_strength.emissiveStrength";
        if (const json* ext = member(m, "extensions", at, true)) {
            const std::string e = at + ".extensions";
            if (const json* x = member(*ext, "KHR_materials_emissive_strength", e, true))
                if (const json* f = member(*x, "emissiveStrength", e + ".KHR_materials_emissive_strength", false))
                    strength = number(*f, strength_at, MaterialParam::EmissiveStrength);
            if (const json* x = member(*ext, "KHR_materials_ior", e, true))
                if (const json* f = member(*x, "ior", e + ".KHR_materials_ior", false))
                    ior = number(*f, e + ".KHR_materials_ior.ior", MaterialParam::Ior);
            if (const json* x = member(*ext, "KHR_materials_transmission", e, true))
                if (const json* f = member(*x, "transmissionFactor", e + ".KHR_materials_transmission", false))
                    transmission = number(*f, e + ".KHR_materials_transmission.transmissionFactor",
                                          MaterialParam::Transparency);
        }
        // Each factor is in range; their product must be too (a strength of 1e6 on a factor of 2).
        for (int c = 0; c < 3; ++c)
            if (const std::string why = material_value_problem(MaterialParam::Emission, emissive[size_t(c)] * strength);
                !why.empty())
                fail(at + ".emissiveFactor[" + std::to_string(c) + "] x " + strength_at, why);
        out.emission = {float(emissive[0] * strength), float(emissive[1] * strength), float(emissive[2] * strength)};
        out.diffuse = {float(base[0]), float(base[1]), float(base[2])};
        out.ior = float(ior);
        // Metallic-roughness, to the nearest of the path tracer's materials (docs/rendering.md): the
        // metallic share of the base colour becomes the specular colour, roughness a Phong exponent
        // (alpha = roughness^2, n = 2 / alpha^2 - 2: rough is broad, smooth a mirror), and
        // KHR_materials_transmission glass.
        if (metallic > 0.0) {
            const Vec3 colour = out.diffuse;
            out.diffuse = colour * float(1.0 - metallic);
            out.specular = colour * float(metallic);
            const double alpha = std::max(roughness * roughness, 1e-3);
            out.shininess = float(std::min(2.0 / (alpha * alpha) - 2.0, kMaxShininess));
        }
        out.dissolve = float(1.0 - transmission);
        return out;
    }

private:
    const std::string& path_;
};

uint32_t read_u32(std::string_view bytes, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);  // GLB is little-endian, as every platform Thicket builds on
    return v;
}

}  // namespace

std::string_view json_text(std::string_view bytes, bool glb, const std::string& path) {
    if (!glb) return bytes;
    if (bytes.size() < 20) throw Error(path + ": GLB header is truncated");
    const uint32_t length = read_u32(bytes, 12), type = read_u32(bytes, 16);
    if (type != 0x4E4F534Au) throw Error(path + ": the first GLB chunk is not JSON");
    if (length > bytes.size() - 20) throw Error(path + ": the GLB JSON chunk runs past the end of the file");
    return bytes.substr(20, length);
}

namespace {

std::vector<Material> read_parsed(const json& doc, const std::string& path) {
    std::vector<Material> out;
    if (!doc.is_object() || !doc.contains("materials")) return out;
    const json& materials = doc.at("materials");
    const MaterialReader reader(path);
    if (!materials.is_array()) reader.fail("materials", "must be an array, got " + shown(materials));
    for (size_t i = 0; i < materials.size(); ++i) out.push_back(reader.read(materials[i], i));
    return out;
}

}  // namespace

std::vector<Material> read_materials(std::string_view text, const std::string& path) {
    json doc;
    try {
        doc = json::parse(text.begin(), text.end());
    } catch (const json::exception& e) {
        throw Error(path + ": invalid glTF JSON: " + e.what());
    }
    return read_parsed(doc, path);
}

std::string material_error(std::string_view bytes, bool glb, const std::string& path) {
    json doc;
    try {
        const std::string_view text = json_text(bytes, glb, path);
        doc = json::parse(text.begin(), text.end());
    } catch (const std::exception&) {
        return "";
    }
    try {
        read_parsed(doc, path);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace thicket::gltf
