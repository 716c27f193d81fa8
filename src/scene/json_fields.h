#pragma once
// Reading one shape object of a JSON scene: typed field accessors whose errors name the file,
// the shape (index and type) and the field, and the table of shape parsers by "type".
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "thicket/core/error.h"  // format_number
#include "thicket/scene/scene.h"

namespace thicket::json_scene {

/// One element of "shapes". Every accessor records its key as known; finish() then rejects any
/// other key. Accessors throw thicket::Error "<file>: shape <i> (<type>): field '<key>': ...".
class ShapeFields {
public:
    ShapeFields(const nlohmann::json& object, std::string file, size_t index, std::string type,
                std::filesystem::path base_dir);

    bool has(const char* key);
    /// A finite number that is also finite as a float.
    float number(const char* key);
    /// A number > 0 (and > 0 as a float).
    float positive(const char* key);
    /// Three finite numbers.
    Vec3 vec3(const char* key);
    /// Three finite numbers, not all zero, normalized (in double, then rounded).
    Vec3 direction(const char* key);
    /// For numbers() and points(): an array of any length but zero.
    static constexpr size_t kAnyCount = 0;
    /// Exactly `n` (or with kAnyCount one or more) finite numbers, in double.
    std::vector<double> numbers(const char* key, size_t n);
    /// Exactly `n` (or with kAnyCount one or more) points [x, y, z], finite as floats.
    std::vector<Vec3> points(const char* key, size_t n);
    /// An integral number in [lo, hi] (3 and 3.0 are both integers).
    long integer(const char* key, long lo, long hi);
    /// A non-empty array of arrays of non-negative integers (a polygon list).
    std::vector<std::vector<uint32_t>> index_lists(const char* key);
    /// A non-empty string.
    std::string string(const char* key);
    /// A string naming an existing file, relative paths taken from the scene file's directory.
    std::string path(const char* key);
    /// The raw value, for kernels with structured data (it must be present).
    const nlohmann::json& value(const char* key);

    /// Throws the error for `key`, e.g. fail("minor_radius", "must be less than major_radius (1)").
    [[noreturn]] void fail(const std::string& key, const std::string& what) const;
    /// Throws an error about the whole shape (no single field at fault).
    [[noreturn]] void fail_shape(const std::string& what) const;
    /// Rejects keys no accessor asked for (other than "type" and the reserved "material").
    void finish() const;

private:
    const nlohmann::json& require(const char* key);
    std::string prefix() const;

    const nlohmann::json& object_;
    std::string file_;
    size_t index_;
    std::string type_;
    std::filesystem::path base_dir_;
    std::vector<std::string> known_;
};

/// A shape "type" and the function that reads its fields and appends it to the scene.
struct ShapeParser {
    const char* type;
    void (*parse)(ShapeFields& fields, Scene& scene);
};

/// Every shape type the JSON format knows, in documentation order (json_shapes.cpp).
std::span<const ShapeParser> shape_parsers();

/// Adds the top-level "instances" array to `scene` (json_instances.cpp): each {"shape": N,
/// "transform": [12 or 16 numbers]} places the geometry entry N of "shapes" made
/// (`entry_prims[N]` its first primitive, entry_prims holding one entry more than there are
/// shapes). Errors name the file and the JSON path (instances[3].transform[5]).
void parse_instances(const nlohmann::json& instances, const std::string& path, const std::vector<uint32_t>& entry_prims,
                     Scene& scene);

/// A JSON value for an error message, shortened.
std::string describe(const nlohmann::json& v);

}  // namespace thicket::json_scene
