#pragma once
/// `thicket compare`'s outputs: the comparison and growth tables (terminal or Markdown), the JSON
/// document, and the two SVG charts per scene (build time against N, Mrays/s per structure).
#include <span>
#include <string>
#include <vector>

#include "thicket/bench/bench_tables.h"
#include "thicket/bench/compare.h"

namespace thicket {

/// How the rows were measured, for the tables' notes and the JSON document.
struct CompareSettings {
    GrowthOptions growth;
    bool growth_measured = true;
    int reps = 5;
    int width = 320, height = 240;  ///< primary set's image size
};

/// "1k", "30k", "1M", "2.5M", or the number with thousands separators when it is not that round.
std::string size_label(size_t n);

/// Per scene (in order of first appearance): the comparison table, one row per structure, then the
/// growth table (build time at every size, the exponent and its fit range), with notes that
/// explain every column and mark. Unmeasurable figures show as an em dash.
std::string format_compare_tables(std::span<const CompareRow> rows, const CompareSettings& settings,
                                  TableStyle style);

/// A JSON object: {"settings": {...}, "rows": [...]}; each row has scene, accel, spec,
/// partitioning, build_ms, bytes, bytes_per_prim, sah_cost (null where undefined), growth (points,
/// exponent, fit range; null with --no-growth) and speed (the bench's rows, bench_json.h).
std::string compare_json(std::span<const CompareRow> rows, const CompareSettings& settings);

/// Log-log chart of build time against N, one line per row that has growth points; rows should
/// be of one scene.
std::string growth_plot_svg(std::span<const CompareRow> rows);
/// Grouped bars of Mrays/s per row: primary and diffuse, on each thread count measured.
std::string speed_plot_svg(std::span<const CompareRow> rows, const CompareSettings& settings);

}  // namespace thicket
