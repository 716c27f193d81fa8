#pragma once
/// Self-contained SVG charts for reports, written by hand (no dependency): a log-log line plot
/// (build time against N) and a grouped bar chart (Mrays/s per structure). Every document is
/// standalone XML (declaration, one <svg> root, text escaped), opens in any browser, and marks its
/// data for tools and tests: each line-plot series is one <polyline class="series"
/// data-series="NAME">, each bar one <rect class="bar" data-series="NAME" data-group="LABEL">.
#include <string>
#include <string_view>
#include <vector>

namespace thicket {

/// `s` escaped for XML text and attribute values (&, <, >, ", ').
std::string xml_escape(std::string_view s);

struct PlotSeries {
    std::string name;
    std::vector<double> x, y;  ///< same length; points with a non-positive or non-finite x or y are left out
};

struct LogLogPlot {
    std::string title;
    std::string x_label, y_label;
    std::vector<PlotSeries> series;
};

/// Both axes logarithmic over whole decades that cover every drawable point (one decade around
/// the points when they all share a value; 1..10 when there are none), labelled ticks and grid
/// lines at each decade, unlabelled minor ticks at 2..9 times a decade, one polyline with point
/// markers per series (a series without drawable points still gets its empty polyline and legend
/// entry), and a legend. Throws Error when a series' x and y differ in length.
std::string svg_log_log_plot(const LogLogPlot& plot);

struct BarGroup {
    std::string label;           ///< shown under the group
    std::vector<double> values;  ///< one per series; a non-finite or negative value draws no bar
};

struct BarChart {
    std::string title;
    std::string y_label;
    std::vector<std::string> series;  ///< bar names, coloured alike in every group and in the legend
    std::vector<BarGroup> groups;
};

/// A linear y axis from 0 to a round value above the largest bar (ticks at 1, 2 or 5 times a power
/// of ten), bars side by side per group with their value on top, group labels slanted when they
/// would not fit side by side, and a legend. Throws Error when a group has not one value per series.
std::string svg_bar_chart(const BarChart& chart);

}  // namespace thicket
