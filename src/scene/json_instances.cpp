// The JSON scene's "instances" (docs/shapes.md, "Instances"): each places the geometry of one
// entry of "shapes" under an affine transform (two-level instancing, instances/instances.h).
#include <cmath>
#include <limits>

#include "json_fields.h"
#include "thicket/core/error.h"

namespace thicket::json_scene {

namespace {

/// The 3x4 transform of `v`: 12 numbers (3x4, row by row) or 16 (4x4 whose last row is 0 0 0 1).
Affine read_transform(const nlohmann::json& v, const std::string& at) {
    const std::string form = "must be an array of 12 numbers (a 3x4 matrix, row by row) or 16 (a 4x4 matrix "
                             "whose last row is 0 0 0 1)";
    if (!v.is_array() || (v.size() != 12 && v.size() != 16)) throw Error(at + ": " + form + ", got " + describe(v));
    double x[16];
    for (size_t k = 0; k < v.size(); ++k) {
        if (!v[k].is_number()) throw Error(at + "[" + std::to_string(k) + "]: " + form + ", got " + describe(v[k]));
        x[k] = v[k].get<double>();
        if (!std::isfinite(x[k]) || std::fabs(x[k]) > double(std::numeric_limits<float>::max()))
            throw Error(at + "[" + std::to_string(k) + "]: must be a finite number, got " + describe(v[k]));
    }
    if (v.size() == 16 && (x[12] != 0.0 || x[13] != 0.0 || x[14] != 0.0 || x[15] != 1.0))
        throw Error(at + ": the last row of a 4x4 transform must be 0 0 0 1 (an affine map), got " +
                    format_number(x[12]) + " " + format_number(x[13]) + " " + format_number(x[14]) + " " +
                    format_number(x[15]));
    Affine t;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.m[r][c] = float(x[4 * r + c]);
    return t;
}

}  // namespace

void parse_instances(const nlohmann::json& instances, const std::string& path, const std::vector<uint32_t>& entry_prims,
                     Scene& scene) {
    if (!instances.is_array()) throw Error(path + ": instances: must be an array, got " + describe(instances));
    const size_t entries = entry_prims.size() - 1;
    for (size_t i = 0; i < instances.size(); ++i) {
        const nlohmann::json& o = instances[i];
        const std::string at = path + ": instances[" + std::to_string(i) + "]";
        if (!o.is_object()) throw Error(at + ": must be an object {\"shape\": N, \"transform\": [...]}, got " + describe(o));
        for (const auto& [key, value] : o.items())
            if (key != "shape" && key != "transform")
                throw Error(at + ": unknown key '" + key + "' (allowed: 'shape', 'transform')");
        if (!o.contains("shape")) throw Error(at + ": missing 'shape' (the index of an entry of 'shapes')");
        if (!o.contains("transform")) throw Error(at + ": missing 'transform' (12 or 16 numbers)");
        const nlohmann::json& s = o.at("shape");
        if (!s.is_number_integer() || s.get<long long>() < 0 || size_t(s.get<long long>()) >= entries)
            throw Error(at + ".shape: must be the index of an entry of 'shapes' (0 to " +
                        std::to_string(entries == 0 ? 0 : entries - 1) + "), got " + describe(s));
        const auto entry = size_t(s.get<long long>());
        if (entry_prims[entry] == entry_prims[entry + 1]) throw Error(at + ".shape: shape " + std::to_string(entry) + " is empty");
        const uint32_t geometry = scene.geometry_of(entry_prims[entry]);
        if (scene.geometry_of(entry_prims[entry + 1] - 1) != geometry)
            throw Error(at + ".shape: shape " + std::to_string(entry) + " made several geometries; it cannot be instanced");
        const Affine t = read_transform(o.at("transform"), at + ".transform");
        try {
            scene.add_instance(geometry, t);
        } catch (const Error& e) {
            // add_instance names the scene; the JSON path is what the author needs.
            const std::string what = e.what();
            const size_t colon = what.find("instance " + std::to_string(scene.instances.size()) + ": ");
            throw Error(at + ".transform: " +
                        (colon == std::string::npos ? what : what.substr(what.find(": ", colon) + 2)));
        }
    }
}

}  // namespace thicket::json_scene
