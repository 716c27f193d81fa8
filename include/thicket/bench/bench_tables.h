#pragma once
/// The bench's human-readable output: per scene, a table of structures (build, memory, SAH) and a
/// table of speed per ray set (Mrays/s on 1 and on all threads, ratio to Embree-high, work per ray,
/// agreement), as padded text for the terminal or as Markdown.
#include <span>
#include <string>

#include "thicket/bench/bench_row.h"

namespace thicket {

enum class TableStyle { Terminal, Markdown };

/// Both tables for every scene in `rows` (in order of first appearance), with a heading per scene
/// and footnotes explaining the marks used.
std::string format_bench_tables(std::span<const BenchRow> rows, TableStyle style);

/// How noisy the timings are: per row, spread = (fastest - slowest pass) / median in Mrays/s.
struct BenchNoise {
    size_t rows = 0;
    double median_spread = 0.0;  ///< in percent
    double p90_spread = 0.0;     ///< 90th percentile, in percent
    double max_spread = 0.0;     ///< in percent
    std::string max_row;         ///< "scene accel set Nt" of the noisiest row
    size_t retried = 0;          ///< rows timed more than once because an attempt was disturbed
    size_t disturbed = 0;        ///< rows still below kDisturbedUtilization in their best attempt
};
BenchNoise bench_noise(std::span<const BenchRow> rows);
/// One sentence describing bench_noise(rows).
std::string format_bench_noise(std::span<const BenchRow> rows);

}  // namespace thicket
