#pragma once
/// The bench's machine-readable output: a JSON array with one object per BenchRow.
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

/// The rows as a JSON array of objects, one per line, ending in a newline. Every field of
/// BenchRow appears under its member name, plus "bytes_per_prim"; unmeasured optional figures and
/// non-finite numbers are null.
std::string bench_rows_json(std::span<const BenchRow> rows);

}  // namespace thicket
