#pragma once
/// The bench's machine-readable output: a JSON array with one object per BenchRow, and the object
/// writer that it and `thicket compare`'s report share.
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "thicket/bench/bench_row.h"

namespace thicket {

/// The fields every row object has, whatever was measured (a figure that could not be measured,
/// such as agreement without Embree, is null rather than missing).
inline constexpr const char* kBenchJsonRequiredFields[] = {"scene", "accel", "set", "threads",
                                                           "mrays", "build_ms", "bytes", "agree"};

/// `s` as a JSON string literal, quotes included: ", \ and control characters escaped, other
/// bytes (UTF-8 included) passed through.
std::string json_quote(std::string_view s);

/// Appends one JSON object to `out`, key by key in call order: `{` on construction, `}` on
/// close(). Numbers print with 9 significant digits; a non-finite number or an absent optional
/// prints null, so a field is never missing.
class JsonObjectWriter {
public:
    explicit JsonObjectWriter(std::string& out) : out_(out) { out_ += "{"; }
    void close() { out_ += "}"; }
    /// `value` as it is: an object or array already written, or a literal.
    void raw(const char* key, const std::string& value) {
        out_ += first_ ? "" : ", ";
        first_ = false;
        out_ += json_quote(key) + ": " + value;
    }
    void str(const char* key, const std::string& v) { raw(key, json_quote(v)); }
    void boolean(const char* key, bool v) { raw(key, v ? "true" : "false"); }
    void integer(const char* key, unsigned long long v) { raw(key, std::to_string(v)); }
    void number(const char* key, double v) { raw(key, number_text(v)); }
    void optional(const char* key, const std::optional<double>& v) { raw(key, v ? number_text(*v) : "null"); }
    /// `v` with 9 significant digits; null when it is not finite.
    static std::string number_text(double v);

private:
    std::string& out_;
    bool first_ = true;
};

/// `rows` as a JSON array of objects, one per line, each filled by write(JsonObjectWriter&, row);
/// "[]" when there are none, no newline after the closing bracket.
template <class Row, class Write>
std::string json_array(std::span<const Row> rows, Write write) {
    std::string out = "[";
    for (size_t i = 0; i < rows.size(); ++i) {
        out += i ? ",\n  " : "\n  ";
        JsonObjectWriter o(out);
        write(o, rows[i]);
        o.close();
    }
    return out + (rows.empty() ? "]" : "\n]");
}

/// The fields that say what a row measured, under their member names: scene, primitives,
/// shapes, accel, spec (BenchRow and CompareRow both start so).
template <class Row>
void write_row_names(JsonObjectWriter& o, const Row& r) {
    o.str("scene", r.scene);
    o.integer("primitives", r.primitives);
    o.integer("shapes", r.shapes);
    o.str("accel", r.accel);
    o.str("spec", r.spec);
}

/// The rows as a JSON array of objects, one per line, ending in a newline. Every field of
/// BenchRow appears under its member name, plus "bytes_per_prim"; unmeasured optional figures and
/// non-finite numbers are null.
std::string bench_rows_json(std::span<const BenchRow> rows);

}  // namespace thicket
