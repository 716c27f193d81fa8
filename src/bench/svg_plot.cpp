#include "thicket/bench/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "thicket/core/error.h"

namespace thicket {

namespace {

// Tableau 10: distinct in colour and in grey; past ten series the dash pattern tells them apart.
constexpr const char* kPalette[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f",
                                    "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};
constexpr size_t kPaletteSize = sizeof kPalette / sizeof kPalette[0];
constexpr const char* kDashes[] = {"", "6 3", "2 3", "8 3 2 3"};

constexpr double kCharWidth = 7.0;  // rough width of a 12px sans-serif character, for layout
constexpr const char* kFont = "font-family=\"sans-serif\"";

const char* colour(size_t i) { return kPalette[i % kPaletteSize]; }
const char* dashes(size_t i) { return kDashes[(i / kPaletteSize) % 4]; }

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}

double text_width(const std::string& s, double char_width = kCharWidth) {
    size_t chars = 0;
    for (unsigned char c : s) chars += (c & 0xC0) != 0x80;  // UTF-8 code points, not bytes
    return double(chars) * char_width;
}

std::string text(double x, double y, const std::string& s, const char* anchor = "middle", int size = 12,
                 const std::string& extra = "") {
    return "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\" text-anchor=\"" + anchor + "\" font-size=\"" +
           std::to_string(size) + "\" " + kFont + (extra.empty() ? "" : " " + extra) + ">" + xml_escape(s) +
           "</text>\n";
}

std::string line(double x1, double y1, double x2, double y2, const char* stroke, double width = 1.0,
                 const std::string& extra = "") {
    return "<line x1=\"" + num(x1) + "\" y1=\"" + num(y1) + "\" x2=\"" + num(x2) + "\" y2=\"" + num(y2) +
           "\" stroke=\"" + stroke + "\" stroke-width=\"" + num(width) + "\"" + (extra.empty() ? "" : " " + extra) +
           "/>\n";
}

std::string header(double width, double height, const std::string& title) {
    return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
           num(width) + "\" height=\"" + num(height) + "\" viewBox=\"0 0 " + num(width) + " " + num(height) +
           "\">\n<title>" + xml_escape(title) + "</title>\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n" +
           text(width / 2, 28, title, "middle", 16, "font-weight=\"bold\"");
}

// A decade's label: 1, 10, 100, 1k ... 100G, 0.1, 0.01, 0.001, else 1e-4 style.
std::string decade_label(int d) {
    static const char* const suffix[] = {"", "k", "M", "G"};
    if (d >= 0 && d < 12) return std::string(d % 3 == 0 ? "1" : d % 3 == 1 ? "10" : "100") + suffix[d / 3];
    if (d < 0 && d >= -3) return "0." + std::string(size_t(-d - 1), '0') + "1";
    return "1e" + std::to_string(d);
}

// About three significant digits, without exponents, for bar values.
std::string value_label(double v) {
    char buf[32];
    const double a = std::fabs(v);
    std::snprintf(buf, sizeof buf, a >= 100 ? "%.0f" : a >= 10 ? "%.1f" : a >= 1 ? "%.2f" : "%.3g", v);
    return buf;
}

// A linear axis tick: as many decimals as the step needs (step 0.2: "0.4"; step 2: "4").
std::string tick_label(double v, double step) {
    const int decimals = std::max(0, int(-std::floor(std::log10(step) + 1e-9)));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

// Legend box at (x, y): one entry per name, drawn by `sample` (the line or swatch) then the name.
template <class Sample>
std::string legend(double x, double y, const std::vector<std::string>& names, Sample sample) {
    std::string out = "<g class=\"legend\">\n";
    for (size_t i = 0; i < names.size(); ++i) {
        const double ly = y + 20.0 * double(i);
        out += sample(i, x, ly);
        out += text(x + 30, ly + 4, names[i], "start");
    }
    return out + "</g>\n";
}

double legend_width(const std::vector<std::string>& names) {
    double w = 0.0;
    for (const std::string& n : names) w = std::max(w, text_width(n));
    return std::min(w, 400.0) + 50.0;
}

}  // namespace

std::string xml_escape(std::string_view s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default:
            // Control characters other than tab and newline are not allowed in XML 1.0 at all.
            if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') {
                out += ' ';
            } else {
                out += c;
            }
        }
    }
    return out;
}

std::string svg_log_log_plot(const LogLogPlot& plot) {
    auto drawable = [](double x, double y) { return x > 0 && y > 0 && std::isfinite(x) && std::isfinite(y); };
    double x_min = INFINITY, x_max = -INFINITY, y_min = INFINITY, y_max = -INFINITY;
    std::vector<std::string> names;
    for (const PlotSeries& s : plot.series) {
        if (s.x.size() != s.y.size())
            throw Error("plot series '" + s.name + "': " + std::to_string(s.x.size()) + " x values but " +
                        std::to_string(s.y.size()) + " y values");
        names.push_back(s.name);
        for (size_t i = 0; i < s.x.size(); ++i) {
            if (!drawable(s.x[i], s.y[i])) continue;
            x_min = std::min(x_min, s.x[i]);
            x_max = std::max(x_max, s.x[i]);
            y_min = std::min(y_min, s.y[i]);
            y_max = std::max(y_max, s.y[i]);
        }
    }
    // Whole decades around the points; the small slack keeps an exact power of ten on its own tick.
    auto decades = [](double lo, double hi, int& a, int& b) {
        if (!(lo <= hi)) lo = hi = 1.0;
        a = int(std::floor(std::log10(lo) + 1e-9));
        b = int(std::ceil(std::log10(hi) - 1e-9));
        if (b <= a) b = a + 1;
    };
    int xa, xb, ya, yb;
    decades(x_min, x_max, xa, xb);
    decades(y_min, y_max, ya, yb);

    const double width = 640.0 + legend_width(names), height = 480.0;
    const double left = 80, top = 50, right = 620, bottom = height - 70;
    auto px = [&](double x) { return left + (std::log10(x) - xa) / double(xb - xa) * (right - left); };
    auto py = [&](double y) { return bottom - (std::log10(y) - ya) / double(yb - ya) * (bottom - top); };

    std::string out = header(width, height, plot.title);
    out += "<g class=\"axes\">\n";
    for (int d = xa; d <= xb; ++d) {
        const double x = px(std::pow(10.0, d));
        out += line(x, top, x, bottom, "#dddddd");
        out += line(x, bottom, x, bottom + 6, "black");
        out += text(x, bottom + 20, decade_label(d));
        if (d < xb)
            for (int m = 2; m <= 9; ++m) out += line(px(m * std::pow(10.0, d)), bottom, px(m * std::pow(10.0, d)),
                                                     bottom + 3, "black");
    }
    for (int d = ya; d <= yb; ++d) {
        const double y = py(std::pow(10.0, d));
        out += line(left, y, right, y, "#dddddd");
        out += line(left - 6, y, left, y, "black");
        out += text(left - 10, y + 4, decade_label(d), "end");
        if (d < yb)
            for (int m = 2; m <= 9; ++m) out += line(left - 3, py(m * std::pow(10.0, d)), left,
                                                     py(m * std::pow(10.0, d)), "black");
    }
    out += "<rect x=\"" + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(right - left) + "\" height=\"" +
           num(bottom - top) + "\" fill=\"none\" stroke=\"black\"/>\n";
    out += text((left + right) / 2, bottom + 45, plot.x_label);
    out += text(0, 0, plot.y_label, "middle", 12,
                "transform=\"translate(" + num(left - 55) + " " + num((top + bottom) / 2) + ") rotate(-90)\"");
    out += "</g>\n";

    for (size_t i = 0; i < plot.series.size(); ++i) {
        const PlotSeries& s = plot.series[i];
        std::string points, markers;
        for (size_t k = 0; k < s.x.size(); ++k) {
            if (!drawable(s.x[k], s.y[k])) continue;
            const double x = px(s.x[k]), y = py(s.y[k]);
            if (!points.empty()) points += ' ';
            points += num(x) + "," + num(y);
            markers += "<circle cx=\"" + num(x) + "\" cy=\"" + num(y) + "\" r=\"3.5\" fill=\"" + colour(i) + "\"/>\n";
        }
        const std::string dash = dashes(i);
        out += "<g class=\"series-group\">\n<polyline class=\"series\" data-series=\"" + xml_escape(s.name) +
               "\" points=\"" + points + "\" fill=\"none\" stroke=\"" + colour(i) + "\" stroke-width=\"2\"" +
               (dash.empty() ? "" : " stroke-dasharray=\"" + dash + "\"") + "><title>" + xml_escape(s.name) +
               "</title></polyline>\n" + markers + "</g>\n";
    }
    out += legend(right + 20, top + 10, names, [](size_t i, double x, double y) {
        const std::string dash = dashes(i);
        return line(x, y, x + 22, y, colour(i), 2.0, dash.empty() ? "" : "stroke-dasharray=\"" + dash + "\"") +
               "<circle cx=\"" + num(x + 11) + "\" cy=\"" + num(y) + "\" r=\"3.5\" fill=\"" + colour(i) + "\"/>\n";
    });
    return out + "</svg>\n";
}

std::string svg_bar_chart(const BarChart& chart) {
    double top_value = 0.0;
    size_t longest = 0;
    for (const BarGroup& g : chart.groups) {
        if (g.values.size() != chart.series.size())
            throw Error("bar group '" + g.label + "': " + std::to_string(g.values.size()) + " values for " +
                        std::to_string(chart.series.size()) + " series");
        for (double v : g.values)
            if (std::isfinite(v)) top_value = std::max(top_value, v);
        longest = std::max(longest, size_t(text_width(g.label)));
    }
    // Round axis: ticks at 1, 2 or 5 times a power of ten, about five of them.
    double step = 1.0;
    if (top_value > 0.0) {
        const double raw = top_value / 5.0, p = std::pow(10.0, std::floor(std::log10(raw)));
        step = raw <= p ? p : raw <= 2 * p ? 2 * p : raw <= 5 * p ? 5 * p : 10 * p;
    } else {
        step = 0.2;
    }
    const double axis_top = top_value > 0.0 ? std::ceil(top_value / step - 1e-9) * step : 1.0;

    const size_t groups = std::max<size_t>(chart.groups.size(), 1);
    const double plot_width = std::max(540.0, 40.0 * double(chart.groups.size() * std::max<size_t>(1, chart.series.size())));
    const double left = 80, top = 50, right = left + plot_width;
    const double slot = (right - left) / double(groups);
    const bool slanted = double(longest) > slot - 6;
    // A label slanted at 35 degrees reaches sin(35) of its length below the axis.
    const double label_depth = slanted ? std::min(260.0, double(longest) * 0.574) + 20 : 20;
    const double bottom = top + 360;
    const double width = right + 20 + legend_width(chart.series);
    const double height = bottom + label_depth + 50;
    auto py = [&](double v) { return bottom - v / axis_top * (bottom - top); };

    std::string out = header(width, height, chart.title);
    out += "<g class=\"axes\">\n";
    for (int k = 0; k * step <= axis_top * (1 + 1e-9); ++k) {
        const double v = k * step, y = py(v);
        out += line(left, y, right, y, "#dddddd");
        out += line(left - 6, y, left, y, "black");
        out += text(left - 10, y + 4, tick_label(v, step), "end");
    }
    out += line(left, top, left, bottom, "black") + line(left, bottom, right, bottom, "black");
    out += text(0, 0, chart.y_label, "middle", 12,
                "transform=\"translate(" + num(left - 55) + " " + num((top + bottom) / 2) + ") rotate(-90)\"");
    out += "</g>\n";

    const double bar = slot * 0.8 / double(std::max<size_t>(chart.series.size(), 1));
    for (size_t g = 0; g < chart.groups.size(); ++g) {
        const BarGroup& group = chart.groups[g];
        const double x0 = left + slot * double(g) + slot * 0.1, centre = left + slot * (double(g) + 0.5);
        out += "<g class=\"bar-group\">\n";
        for (size_t s = 0; s < group.values.size(); ++s) {
            const double v = group.values[s];
            if (!std::isfinite(v) || v < 0.0) continue;
            const double x = x0 + bar * double(s), y = py(v);
            out += "<rect class=\"bar\" data-series=\"" + xml_escape(chart.series[s]) + "\" data-group=\"" +
                   xml_escape(group.label) + "\" x=\"" + num(x) + "\" y=\"" + num(y) + "\" width=\"" +
                   num(bar * 0.92) + "\" height=\"" + num(bottom - y) + "\" fill=\"" + colour(s) + "\"><title>" +
                   xml_escape(group.label + ", " + chart.series[s] + ": " + value_label(v)) + "</title></rect>\n";
            const std::string label = value_label(v);
            if (bar >= text_width(label, 6.0) + 2)
                out += text(x + bar * 0.46, y - 4, label, "middle", 10);
            else
                out += text(0, 0, label, "start", 10,
                            "transform=\"translate(" + num(x + bar * 0.46 + 3) + " " + num(y - 4) + ") rotate(-90)\"");
        }
        if (slanted)
            out += text(0, 0, group.label, "end", 12,
                        "transform=\"translate(" + num(centre) + " " + num(bottom + 16) + ") rotate(-35)\"");
        else
            out += text(centre, bottom + 18, group.label);
        out += "</g>\n";
    }
    out += legend(right + 20, top + 10, chart.series, [](size_t i, double x, double y) {
        return "<rect x=\"" + num(x) + "\" y=\"" + num(y - 6) + "\" width=\"22\" height=\"12\" fill=\"" + colour(i) +
               "\"/>\n";
    });
    return out + "</svg>\n";
}

}  // namespace thicket
