// The JSON scene format (docs/shapes.md): the file, its top-level keys, and the typed field
// accessors every shape parser uses. The shape types themselves are in json_shapes.cpp.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include "json_fields.h"
#include "thicket/core/error.h"
#include "thicket/util/input_file.h"
#include "thicket/scene/loaders.h"

namespace thicket {

namespace json_scene {

using nlohmann::json;

namespace {

/// Top-level keys the renderer will define: accepted and ignored until then.
constexpr const char* kReservedTopLevel[] = {"camera", "materials", "lights"};
/// Shape keys reserved the same way.
constexpr const char* kReservedShapeKey = "material";

std::string type_list() {
    std::string out;
    for (const ShapeParser& p : shape_parsers()) out += (out.empty() ? "" : ", ") + std::string(p.type);
    return out;
}

const char* kind_of(const json& v) {
    switch (v.type()) {
        case json::value_t::null: return "null";
        case json::value_t::boolean: return "a boolean";
        case json::value_t::string: return "a string";
        case json::value_t::array: return "an array";
        case json::value_t::object: return "an object";
        default: return "a number";
    }
}

bool is_float_finite(double x) {
    return std::isfinite(x) && std::fabs(x) <= double(std::numeric_limits<float>::max());
}

}  // namespace

std::string describe(const json& v) {
    std::string s = v.dump();
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return s;
}

ShapeFields::ShapeFields(const json& object, std::string file, size_t index, std::string type,
                         std::filesystem::path base_dir)
    : object_(object), file_(std::move(file)), index_(index), type_(std::move(type)), base_dir_(std::move(base_dir)) {}

std::string ShapeFields::prefix() const {
    return file_ + ": shape " + std::to_string(index_) + " (" + type_ + ")";
}

void ShapeFields::fail(const std::string& key, const std::string& what) const {
    throw Error(prefix() + ": field '" + key + "': " + what);
}

void ShapeFields::fail_shape(const std::string& what) const { throw Error(prefix() + ": " + what); }

bool ShapeFields::has(const char* key) {
    known_.push_back(key);
    return object_.contains(key);
}

const json& ShapeFields::require(const char* key) {
    if (!has(key)) {
        std::string given;
        for (const auto& [k, v] : object_.items()) given += (given.empty() ? "" : ", ") + k;
        fail(key, "missing (fields given: " + given + ")");
    }
    return object_.at(key);
}

const json& ShapeFields::value(const char* key) { return require(key); }

float ShapeFields::number(const char* key) {
    const json& v = require(key);
    if (!v.is_number()) fail(key, std::string("must be a number, got ") + kind_of(v) + " " + describe(v));
    const double x = v.get<double>();
    if (!is_float_finite(x)) fail(key, "must be a finite number within the float range, got " + describe(v));
    return float(x);
}

float ShapeFields::positive(const char* key) {
    const float x = number(key);
    if (!(x > 0.0f)) fail(key, "must be a positive number, got " + describe(object_.at(key)));
    return x;
}

std::vector<double> ShapeFields::numbers(const char* key, size_t n) {
    const json& v = require(key);
    const bool any = n == kAnyCount;
    if (!v.is_array() || (any ? v.empty() : v.size() != n))
        fail(key, "must be an array of " + (any ? std::string("one or more") : std::to_string(n)) + " numbers, got " +
                      (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(kind_of(v))) + " " +
                      describe(v));
    std::vector<double> out;
    for (size_t i = 0; i < v.size(); ++i) {
        if (!v[i].is_number())
            fail(key, "element " + std::to_string(i) + " must be a number, got " + kind_of(v[i]) + " " + describe(v[i]));
        out.push_back(v[i].get<double>());
        if (!is_float_finite(out.back()))
            fail(key, "element " + std::to_string(i) + " must be a finite number within the float range, got " +
                          describe(v[i]));
    }
    return out;
}

std::vector<Vec3> ShapeFields::points(const char* key, size_t n) {
    const json& v = require(key);
    const bool any = n == kAnyCount;
    if (!v.is_array() || (any ? v.empty() : v.size() != n))
        fail(key, "must be an array of " + (any ? std::string("one or more") : std::to_string(n)) +
                      " points [x, y, z], got " +
                      (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(kind_of(v))) + " " +
                      describe(v));
    std::vector<Vec3> out;
    for (size_t i = 0; i < v.size(); ++i) {
        const json& p = v[i];
        if (!p.is_array() || p.size() != 3)
            fail(key, "element " + std::to_string(i) + " must be a point [x, y, z], got " + describe(p));
        double c[3];
        for (int k = 0; k < 3; ++k) {
            if (!p[k].is_number() || !is_float_finite(p[k].get<double>()))
                fail(key, "element " + std::to_string(i) + " must be a point of 3 finite numbers within the float "
                          "range, got " + describe(p));
            c[k] = p[k].get<double>();
        }
        out.push_back({float(c[0]), float(c[1]), float(c[2])});
    }
    return out;
}

long ShapeFields::integer(const char* key, long lo, long hi) {
    const json& v = require(key);
    const bool integral = v.is_number_integer() || (v.is_number_float() && std::isfinite(v.get<double>()) &&
                                                    std::floor(v.get<double>()) == v.get<double>());
    if (!integral) fail(key, std::string("must be an integer, got ") + kind_of(v) + " " + describe(v));
    const double x = v.get<double>();
    if (x < double(lo) || x > double(hi))
        fail(key, "must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " + describe(v));
    return long(x);
}

std::vector<std::vector<uint32_t>> ShapeFields::index_lists(const char* key) {
    const json& v = require(key);
    if (!v.is_array() || v.empty())
        fail(key, std::string("must be a non-empty array of index arrays, got ") + kind_of(v) + " " + describe(v));
    std::vector<std::vector<uint32_t>> out;
    for (size_t i = 0; i < v.size(); ++i) {
        const json& list = v[i];
        if (!list.is_array()) fail(key, "element " + std::to_string(i) + " must be an array of indices, got " + describe(list));
        std::vector<uint32_t> indices;
        for (const json& x : list) {
            if (!x.is_number_unsigned() || x.get<uint64_t>() > 0xffffffffu)
                fail(key, "element " + std::to_string(i) + " must hold indices (integers >= 0), got " + describe(list));
            indices.push_back(uint32_t(x.get<uint64_t>()));
        }
        out.push_back(std::move(indices));
    }
    return out;
}

Vec3 ShapeFields::vec3(const char* key) {
    const std::vector<double> v = numbers(key, 3);
    return {float(v[0]), float(v[1]), float(v[2])};
}

Vec3 ShapeFields::direction(const char* key) {
    const std::vector<double> v = numbers(key, 3);
    const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(len > 0.0) || !std::isfinite(len)) fail(key, "must be a non-zero direction, got " + describe(object_.at(key)));
    return {float(v[0] / len), float(v[1] / len), float(v[2] / len)};
}

std::string ShapeFields::string(const char* key) {
    const json& v = require(key);
    if (!v.is_string() || v.get<std::string>().empty())
        fail(key, std::string("must be a non-empty string, got ") + kind_of(v) + " " + describe(v));
    return v.get<std::string>();
}

std::string ShapeFields::path(const char* key) {
    const std::filesystem::path p(string(key));
    const std::filesystem::path full = p.is_absolute() ? p : base_dir_ / p;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(full, ec)) fail(key, "no such file: " + full.string());
    return full.string();
}

void ShapeFields::finish() const {
    for (const auto& [k, v] : object_.items()) {
        if (k == "type" || k == kReservedShapeKey) continue;
        bool ok = false;
        for (const std::string& known : known_) ok = ok || known == k;
        if (ok) continue;
        std::string allowed;
        for (const std::string& known : known_)
            if (allowed.find("'" + known + "'") == std::string::npos) allowed += (allowed.empty() ? "" : ", ") + ("'" + known + "'");
        fail(k, "unknown field for a " + type_ + " (its fields: " + allowed + ", and the reserved 'material')");
    }
}

namespace {

/// Parses the text, refusing duplicate keys (nlohmann would keep the last one silently); the
/// message names the shape when the duplicate is inside one.
/// nlohmann's DOM builder with duplicate keys refused. (json::parse with a callback did this
/// before, but its callback parser scans the whole parent array at every object's end: a scene
/// of N shapes loaded in O(N^2), 200,000 spheres in 7 s.)
class CheckedDomParser : public nlohmann::detail::json_sax_dom_parser<json> {
public:
    CheckedDomParser(json& result, const std::string& file) : json_sax_dom_parser(result, true), file_(file) {}

    bool start_object(std::size_t n) {
        if (open_ == 2 && top_key_ == "shapes") ++shape_;
        keys_.emplace_back();
        ++open_;
        return json_sax_dom_parser::start_object(n);
    }
    bool end_object() {
        keys_.pop_back();
        --open_;
        return json_sax_dom_parser::end_object();
    }
    bool start_array(std::size_t n) {
        ++open_;
        return json_sax_dom_parser::start_array(n);
    }
    bool end_array() {
        --open_;
        return json_sax_dom_parser::end_array();
    }
    bool key(string_t& k) {
        if (open_ == 1) top_key_ = k;
        if (!keys_.empty() && !keys_.back().insert(k).second) {
            const std::string where = open_ == 1 ? "top-level key"
                                      : (top_key_ == "shapes" && shape_ >= 0 && open_ >= 3
                                             ? "shape " + std::to_string(shape_) + ": field"
                                             : "key");
            throw Error(file_ + ": " + where + " '" + k + "' given twice");
        }
        return json_sax_dom_parser::key(k);
    }

private:
    const std::string& file_;
    std::vector<std::set<std::string>> keys_;  // one set per open object
    std::string top_key_;
    long shape_ = -1;
    int open_ = 0;  // objects and arrays open
};

json parse_checked(const std::string& text, const std::string& file) {
    try {
        json result;
        CheckedDomParser sax(result, file);
        json::sax_parse(text, &sax);
        return result;
    } catch (const json::exception& e) {
        std::string what = e.what();
        const size_t close = what.find("] ");  // drop nlohmann's "[json.exception.parse_error.101] "
        if (close != std::string::npos) what = what.substr(close + 2);
        throw Error(file + ": invalid JSON: " + what);
    }
}

}  // namespace

}  // namespace json_scene

Scene load_json_scene(const std::string& path) {
    std::vector<uint32_t> entry_prims;
    return load_json_scene(path, entry_prims);
}

Scene load_json_scene(const std::string& path, std::vector<uint32_t>& entry_prims) {
    using namespace json_scene;
    entry_prims.clear();
    const json doc = parse_checked(read_input_file(path, "JSON scene"), path);

    if (!doc.is_object()) throw Error(path + ": a JSON scene must be an object with a \"shapes\" array");
    for (const auto& [key, v] : doc.items()) {
        bool ok = key == "shapes" || key == "instances";
        for (const char* r : kReservedTopLevel) ok = ok || key == r;
        if (!ok)
            throw Error(path + ": unknown top-level key '" + key +
                        "' (allowed: 'shapes', 'instances', and 'camera', 'materials', 'lights', reserved for the renderer)");
    }
    if (!doc.contains("shapes")) throw Error(path + ": missing top-level key 'shapes' (an array of shapes)");
    const json& shapes = doc.at("shapes");
    if (!shapes.is_array()) throw Error(path + ": 'shapes' must be an array, got " + describe(shapes));

    Scene scene;
    scene.name = path;
    const std::filesystem::path base = std::filesystem::path(path).parent_path();
    for (size_t i = 0; i < shapes.size(); ++i) {
        const json& s = shapes[i];
        const std::string at = path + ": shape " + std::to_string(i);
        if (!s.is_object()) throw Error(at + ": must be an object, got " + describe(s));
        if (!s.contains("type")) throw Error(at + ": missing field 'type' (one of: " + type_list() + ")");
        if (!s.at("type").is_string())
            throw Error(at + ": field 'type' must be a string (one of: " + type_list() + "), got " + describe(s.at("type")));
        const std::string type = s.at("type").get<std::string>();
        const ShapeParser* parser = nullptr;
        for (const ShapeParser& p : shape_parsers())
            if (type == p.type) parser = &p;
        if (!parser) throw Error(at + ": unknown type '" + type + "' (known types: " + type_list() + ")");

        ShapeFields fields(s, path, i, type, base);
        const size_t shapes_before = scene.shapes.size();
        entry_prims.push_back(uint32_t(scene.primitive_count()));
        parser->parse(fields, scene);
        fields.finish();
        for (size_t k = shapes_before; k < scene.shapes.size(); ++k) {
            const Aabb b = shape_bounds(scene.shapes[k]);
            for (int a = 0; a < 3; ++a)
                if (!std::isfinite(b.min[a]) || !std::isfinite(b.max[a]))
                    fields.fail_shape("its bounds exceed the float range (" + format_number(b.min[a]) + " .. " +
                                      format_number(b.max[a]) + " on axis " + std::to_string(a) + ")");
        }
    }
    entry_prims.push_back(uint32_t(scene.primitive_count()));
    if (doc.contains("instances")) parse_instances(doc.at("instances"), path, entry_prims, scene);
    return scene;
}

}  // namespace thicket
