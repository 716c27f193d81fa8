#include "thicket/render/render_json.h"

#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/material_ranges.h"

namespace thicket {

namespace {

using json = nlohmann::json;

struct Reader {
    std::string at;  // "file: materials.glass" style prefix for messages

    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw Error(at + (key.empty() ? "" : "." + key) + ": " + what);
    }
    float number(const json& v, const std::string& key) const {
        if (!v.is_number()) fail(key, "must be a number");
        const double x = v.get<double>();
        if (!std::isfinite(x)) fail(key, "must be finite");
        return float(x);
    }
    /// [x, y, z], or for colours also a single number meaning grey.
    Vec3 vec3(const json& v, const std::string& key, bool grey_allowed) const {
        if (grey_allowed && v.is_number()) return Vec3{number(v, key)};
        if (!v.is_array() || v.size() != 3)
            fail(key, grey_allowed ? "must be [r, g, b] or one number" : "must be [x, y, z]");
        return {number(v[0], key), number(v[1], key), number(v[2], key)};
    }
    Vec3 colour(const json& v, const std::string& key) const {
        const Vec3 c = vec3(v, key, true);
        if (c.x < 0 || c.y < 0 || c.z < 0) fail(key, "must not be negative");
        return c;
    }
};

/// A material parameter, checked against the shared table (thicket/scene/material_ranges.h).
double material_number(const json& v, const std::string& key, MaterialParam p, const Reader& r) {
    if (!v.is_number()) r.fail(key, "must be a number, got " + v.dump());
    const double x = v.get<double>();
    if (const std::string why = material_value_problem(p, x); !why.empty()) r.fail(key, why);
    return x;
}

/// A material colour: [r, g, b] or one number for grey, each channel checked against the table.
Vec3 material_colour(const json& v, const std::string& key, MaterialParam p, const Reader& r) {
    if (v.is_number()) return Vec3{float(material_number(v, key, p, r))};
    if (!v.is_array() || v.size() != 3) r.fail(key, "must be [r, g, b] or one number, got " + v.dump());
    double c[3];
    for (size_t i = 0; i < 3; ++i) c[i] = material_number(v[i], key + "[" + std::to_string(i) + "]", p, r);
    return {float(c[0]), float(c[1]), float(c[2])};
}

SurfaceMaterial parse_material(const json& m, const std::string& name, const Reader& r) {
    if (!m.is_object()) r.fail("", "a material must be an object of MTL-style fields (kd, ks, ke, ns, ni, d, illum)");
    Material mtl;
    mtl.name = name;
    mtl.diffuse = Vec3{0.8f};
    bool two_sided = false;
    for (const auto& [key, v] : m.items()) {
        if (key == "kd") mtl.diffuse = material_colour(v, key, MaterialParam::Diffuse, r);
        else if (key == "ks") mtl.specular = material_colour(v, key, MaterialParam::Specular, r);
        else if (key == "ke") mtl.emission = material_colour(v, key, MaterialParam::Emission, r);
        else if (key == "ns") mtl.shininess = float(material_number(v, key, MaterialParam::Shininess, r));
        else if (key == "ni") mtl.ior = float(material_number(v, key, MaterialParam::Ior, r));
        else if (key == "d") mtl.dissolve = float(material_number(v, key, MaterialParam::Dissolve, r));
        else if (key == "illum") mtl.illum = int(material_number(v, key, MaterialParam::Illum, r));  // whole, 0..10
        else if (key == "two_sided") {
            if (!v.is_boolean()) r.fail(key, "must be true or false");
            two_sided = v.get<bool>();
        } else {
            r.fail(key, "unknown material field (fields: kd, ks, ke, ns, ni, d, illum, two_sided)");
        }
    }
    SurfaceMaterial s = surface_from_material(mtl);
    s.two_sided = two_sided;
    return s;
}

}  // namespace

void apply_json_render_settings(const std::string& path, RenderScene& rs) {
    if (!rs.scene) throw Error(path + ": no scene to apply materials to");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open");
    std::ostringstream text;
    text << in.rdbuf();
    json doc;
    try {
        doc = json::parse(text.str());
    } catch (const json::exception& e) {
        throw Error(path + ": invalid JSON: " + e.what());
    }
    if (!doc.is_object()) return;

    std::map<std::string, uint32_t> by_name;
    if (doc.contains("materials")) {
        const json& mats = doc.at("materials");
        if (!mats.is_object()) throw Error(path + ": 'materials' must be an object of named materials");
        for (const auto& [name, m] : mats.items()) {
            rs.materials.push_back(parse_material(m, name, Reader{path + ": materials." + name}));
            by_name[name] = uint32_t(rs.materials.size() - 1);
        }
    }
    if (doc.contains("shapes") && doc.at("shapes").is_array()) {
        const json& shapes = doc.at("shapes");
        // Which ids each entry made: the loader knows (a mesh's triangles, the teapot's 32 patches).
        std::vector<uint32_t> first;
        const Scene again = load_json_scene(path, first);
        if (first.size() != shapes.size() + 1 || again.primitive_count() != rs.scene->primitive_count())
            throw Error(path + ": the scene was not loaded from this file (its primitive count differs)");
        for (size_t i = 0; i < shapes.size(); ++i) {
            if (!shapes[i].is_object() || !shapes[i].contains("material")) continue;
            const json& name = shapes[i].at("material");
            const std::string at = path + ": shape " + std::to_string(i) + ".material";
            if (!name.is_string()) throw Error(at + ": must be the name of an entry of 'materials'");
            const auto it = by_name.find(name.get<std::string>());
            if (it == by_name.end())
                throw Error(at + ": no material named '" + name.get<std::string>() + "' in 'materials'");
            for (uint32_t p = first[i]; p < first[i + 1]; ++p) rs.prim_material[p] = it->second;
        }
    }
    if (doc.contains("lights")) {
        const json& lights = doc.at("lights");
        if (!lights.is_array()) throw Error(path + ": 'lights' must be an array");
        for (size_t i = 0; i < lights.size(); ++i) {
            const Reader r{path + ": lights[" + std::to_string(i) + "]"};
            const json& l = lights[i];
            if (!l.is_object()) r.fail("", "must be an object");
            if (!l.contains("type") || l.at("type") != "point")
                r.fail("type", "must be \"point\" (area lights are shapes with an emissive material)");
            if (!l.contains("position")) r.fail("position", "missing");
            PointLight pl;
            pl.position = r.vec3(l.at("position"), "position", false);
            pl.intensity = l.contains("intensity") ? r.colour(l.at("intensity"), "intensity") : Vec3{1.0f};
            for (const auto& [key, v] : l.items())
                if (key != "type" && key != "position" && key != "intensity")
                    r.fail(key, "unknown light field (fields: type, position, intensity)");
            rs.point_lights.push_back(pl);
        }
    }
    if (doc.contains("camera")) {
        const Reader r{path + ": camera"};
        const json& c = doc.at("camera");
        if (!c.is_object() || !c.contains("position") || !c.contains("target"))
            r.fail("", "must be an object with position and target (and optionally fov, up)");
        const Vec3 pos = r.vec3(c.at("position"), "position", false), target = r.vec3(c.at("target"), "target", false);
        const Vec3 up = c.contains("up") ? r.vec3(c.at("up"), "up", false) : Vec3{0, 1, 0};
        const float fov = c.contains("fov") ? r.number(c.at("fov"), "fov") : kDefaultFovDegrees;
        for (const auto& [key, v] : c.items())
            if (key != "position" && key != "target" && key != "up" && key != "fov")
                r.fail(key, "unknown camera field (fields: position, target, up, fov)");
        try {
            rs.camera = Camera(pos, target, up, fov);
        } catch (const Error& e) {
            r.fail("", e.what());
        }
    }
}

}  // namespace thicket
