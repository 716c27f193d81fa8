#include "thicket/bench/compare_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "thicket/bench/bench_json.h"
#include "thicket/bench/svg_plot.h"
#include "thicket/bench/number_text.h"
#include "thicket/bench/text_table.h"

namespace thicket {

namespace {

using Align = TextTable::Align;
const std::string kDash = "\u2014";  // em dash: not measured, or undefined for this structure

std::string fixed3_or_dash(double v) { return three_digits(v, kDash); }

std::vector<unsigned> thread_counts(const std::vector<const CompareRow*>& rows) {
    std::vector<unsigned> threads;
    for (const CompareRow* r : rows)
        for (const BenchRow& b : r->speed)
            if (std::find(threads.begin(), threads.end(), b.threads) == threads.end()) threads.push_back(b.threads);
    std::sort(threads.begin(), threads.end());
    return threads;
}

std::string threads_text(const std::vector<unsigned>& threads) {
    std::string out;
    for (unsigned t : threads) {
        if (!out.empty()) out += '/';
        out += std::to_string(t) + "t";
    }
    return out;
}

std::string thread_words(unsigned t) { return std::to_string(t) + (t == 1 ? " thread" : " threads"); }

std::vector<std::vector<const CompareRow*>> by_scene(std::span<const CompareRow> rows) {
    std::vector<std::vector<const CompareRow*>> out;
    for (const CompareRow& r : rows) {
        auto it = std::find_if(out.begin(), out.end(), [&](const auto& s) { return s.front()->scene == r.scene; });
        if (it == out.end())
            out.push_back({&r});
        else
            it->push_back(&r);
    }
    return out;
}

// "a / b" of one set's Mrays/s on each thread count, with the bench's marks.
std::string speed_cell(const CompareRow& r, const char* set, const std::vector<unsigned>& threads, bool& sampled,
                       bool& disturbed) {
    std::string cell;
    size_t stride = 1;
    for (unsigned t : threads) {
        const BenchRow* b = r.find(set, t);
        if (!cell.empty()) cell += " / ";
        cell += b ? fixed3_or_dash(b->mrays) : kDash;
        if (b && b->cpu_util < kDisturbedUtilization) {
            cell += "!";
            disturbed = true;
        }
        if (b) stride = std::max(stride, b->stride);
    }
    if (stride > 1) {
        cell += " (1/" + std::to_string(stride) + ")";
        sampled = true;
    }
    return cell;
}

std::string work_cell(const CompareRow& r, const char* set, const std::vector<unsigned>& threads) {
    const BenchRow* b = threads.empty() ? nullptr : r.find(set, threads.front());
    if (!b || !b->nodes_per_ray || !b->prims_per_ray) return kDash;
    return fixed3_or_dash(*b->nodes_per_ray) + " / " + fixed3_or_dash(*b->prims_per_ray);
}

std::string fit_range(const PowerFit& f) {
    if (!f.valid()) return kDash;
    return size_label(size_t(f.min_n)) + "\u2013" + size_label(size_t(f.max_n)) + ", " + std::to_string(f.points) +
           " sizes, R\u00b2 " + printf_string("%.3f", f.r2);
}

std::string scene_section(const std::vector<const CompareRow*>& rows, const CompareSettings& settings,
                          TableStyle style) {
    const bool md = style == TableStyle::Markdown;
    auto render = [&](const TextTable& t) { return md ? t.markdown() : t.terminal(); };
    const std::vector<unsigned> threads = thread_counts(rows);
    const CompareRow& first = *rows.front();

    std::string out;
    const std::string about = primitives_text(first.primitives, first.shapes) + "; primary rays " +
                              std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                              "; Mrays/s on " + threads_text(threads) + "; builds on 1 thread";
    out += md ? "### " + first.scene + "\n\n" + about + ".\n\n" : "== " + first.scene + ": " + about + "\n\n";

    const std::string tt = threads_text(threads);
    TextTable table({"structure", "partitioning", "build ms", "growth k", "B/prim", "SAH cost",
                     "primary Mrays/s " + tt, "primary nodes/prims", "diffuse Mrays/s " + tt, "diffuse nodes/prims"},
                    {Align::Left, Align::Left, Align::Right, Align::Right, Align::Right, Align::Right, Align::Right,
                     Align::Right, Align::Right, Align::Right});
    bool sampled = false, disturbed = false, stopped = false;
    for (const CompareRow* r : rows) {
        const bool has_fit = r->growth && r->growth->fit.valid();
        table.add_row({r->accel, partitioning_name(r->partitioning),
                       r->speed.empty() ? kDash : fixed3_or_dash(r->build_ms()),
                       has_fit ? printf_string("%.2f", r->growth->fit.exponent) : kDash,
                       r->speed.empty() ? kDash : printf_string("%.1f", r->structure_bytes_per_primitive()),
                       r->sah_cost() > 0.0 ? printf_string("%.2f", r->sah_cost()) : kDash,
                       speed_cell(*r, "primary", threads, sampled, disturbed), work_cell(*r, "primary", threads),
                       speed_cell(*r, "diffuse", threads, sampled, disturbed), work_cell(*r, "diffuse", threads)});
    }
    out += render(table) + "\n";

    const GrowthOptions& g = settings.growth;
    if (settings.growth_measured) {
        std::vector<std::string> head{"structure"};
        std::vector<Align> align{Align::Left};
        for (size_t n : g.sizes) {
            head.push_back("N=" + size_label(n));
            align.push_back(Align::Right);
        }
        head.insert(head.end(), {"growth k", "fit over"});
        align.insert(align.end(), {Align::Right, Align::Left});
        TextTable growth(head, align);
        for (const CompareRow* r : rows) {
            std::vector<std::string> cells{r->accel};
            for (size_t n : g.sizes) {
                std::string cell = kDash;
                if (r->growth) {
                    for (const GrowthPoint& p : r->growth->points)
                        if (p.n == n) cell = fixed3_or_dash(p.build_ms);
                    if (r->growth->stopped_at && *r->growth->stopped_at == n) {
                        cell += "*";
                        stopped = true;
                    }
                }
                cells.push_back(cell);
            }
            const bool has_fit = r->growth && r->growth->fit.valid();
            cells.push_back(has_fit ? printf_string("%.2f", r->growth->fit.exponent) : kDash);
            cells.push_back(r->growth ? fit_range(r->growth->fit) : kDash);
            growth.add_row(cells);
        }
        out += (md ? "Build time in ms against N:\n\n" : "build ms against N\n") + render(growth) + "\n";
    }

    std::vector<std::string> notes;
    notes.push_back("partitioning: object = the primitives are grouped, each in one leaf, and group bounds may "
                    "overlap; space = space is cut into disjoint cells and a primitive is referenced by every cell "
                    "it overlaps; none = no structure.");
    notes.push_back("build ms: one build of the whole scene on 1 thread.");
    if (settings.growth_measured)
        notes.push_back(
            "growth k: the exponent of build ms ~ N^k, a least-squares line through log(build ms) against log(N) "
            "over the sizes N >= " + size_label(size_t(g.fit_min_size)) +
            " (smaller builds take too little time to show the growth); 1 is linear, about 1.09 is N log N over "
            "10k-1M, 2 quadratic. A scene of N triangles is a random subset of the scene's triangles (fixed "
            "seed), or, when the scene has fewer than N, of its triangles split into four by their edge "
            "midpoints as often as needed. Each size is built up to " + std::to_string(g.max_builds) +
            " times (fewer once the builds took " + printf_string("%.0f", g.repeat_budget_ms) +
            " ms in all) and the median kept.");
    else
        notes.push_back("growth k: not measured (--no-growth).");
    if (stopped)
        notes.push_back("*: this size and the larger ones were skipped: the build was predicted to take longer "
                        "than the build budget of " + printf_string("%.0f", g.build_budget_s) + " s (--build-budget).");
    notes.push_back("B/prim: the structure's memory (nodes, cells and index arrays; not the triangles) per triangle.");
    notes.push_back("SAH cost: with C_trav = C_isect = 1, relative to the root's area; " + kDash +
                    " where the structure defines none.");
    notes.push_back("Mrays/s: the rays of `thicket rays --set primary|diffuse` (diffuse: one cosine-weighted bounce "
                    "per primary hit), median of " + std::to_string(settings.reps) + " timed passes after a "
                    "warm-up, on " + tt + " as in `thicket bench`.");
    notes.push_back("nodes/prims: nodes (or cells) visited and primitives tested per ray, from an untimed counting "
                    "pass over the same rays.");
    if (sampled)
        notes.push_back("1/k: timed on every k-th ray of the set, because a single-thread pass over the whole set "
                        "was estimated to take longer than the pass budget (--pass-budget).");
    if (disturbed)
        notes.push_back("!: other work on the machine took CPU time from these passes: the figure is too low.");
    for (const std::string& n : notes) out += (md ? "- " : "  ") + n + "\n";
    return out;
}

std::string growth_json(const Growth& g) {
    std::string out;
    JsonObjectWriter o(out);
    std::string points = "[";
    for (const GrowthPoint& p : g.points) {
        if (points.size() > 1) points += ", ";
        JsonObjectWriter po(points);
        po.integer("n", p.n);
        po.number("build_ms", p.build_ms);
        po.integer("builds", (unsigned long long)p.builds);
        po.close();
    }
    o.raw("points", points + "]");
    o.number("exponent", g.fit.valid() ? g.fit.exponent : NAN);
    o.number("coefficient", g.fit.valid() ? g.fit.coefficient : NAN);
    o.number("r2", g.fit.valid() ? g.fit.r2 : NAN);
    o.integer("fit_points", g.fit.points);
    o.raw("fit_min_n", g.fit.valid() ? std::to_string(size_t(g.fit.min_n)) : "null");
    o.raw("fit_max_n", g.fit.valid() ? std::to_string(size_t(g.fit.max_n)) : "null");
    o.raw("stopped_at", g.stopped_at ? std::to_string(*g.stopped_at) : "null");
    o.number("stopped_predicted_s", g.stopped_at ? g.predicted_s : NAN);
    o.close();
    return out;
}

}  // namespace

std::string size_label(size_t n) {
    for (auto [unit, suffix] : {std::pair<size_t, const char*>{1'000'000, "M"}, {1'000, "k"}}) {
        if (n < unit) continue;
        if (n % unit == 0) return std::to_string(n / unit) + suffix;
        if (n % (unit / 10) == 0) return printf_string("%.1f", double(n) / double(unit)) + suffix;
    }
    return grouped(n);
}

std::string format_compare_tables(std::span<const CompareRow> rows, const CompareSettings& settings,
                                  TableStyle style) {
    std::string out;
    for (const auto& scene : by_scene(rows)) {
        if (!out.empty()) out += '\n';
        out += scene_section(scene, settings, style);
    }
    return out;
}

std::string compare_json(std::span<const CompareRow> rows, const CompareSettings& settings) {
    std::string out;
    JsonObjectWriter doc(out);
    std::string s;
    {
        JsonObjectWriter o(s);
        std::string sizes = "[";
        for (size_t n : settings.growth.sizes) sizes += (sizes.size() > 1 ? ", " : "") + std::to_string(n);
        o.raw("growth_sizes", settings.growth_measured ? sizes + "]" : "null");
        o.number("fit_min_n", settings.growth.fit_min_size);
        o.integer("max_builds", (unsigned long long)settings.growth.max_builds);
        o.number("build_budget_s", settings.growth.build_budget_s);
        o.integer("build_threads", 1);
        o.integer("reps", (unsigned long long)settings.reps);
        o.integer("width", (unsigned long long)settings.width);
        o.integer("height", (unsigned long long)settings.height);
        o.close();
    }
    doc.raw("settings", s);
    doc.raw("rows", json_array(rows, [&](JsonObjectWriter& o, const CompareRow& r) {
        write_row_names(o, r);
        o.str("partitioning", partitioning_name(r.partitioning));
        o.number("build_ms", r.speed.empty() ? NAN : r.build_ms());
        o.integer("structure_bytes", r.structure_bytes());
        o.integer("primitive_bytes", r.speed.empty() ? 0 : r.speed.front().primitive_bytes);
        o.number("bytes_per_prim", r.speed.empty() ? NAN : r.structure_bytes_per_primitive());
        o.integer("nodes", r.speed.empty() ? 0 : r.speed.front().nodes);
        o.number("sah_cost", r.sah_cost() > 0.0 ? r.sah_cost() : NAN);
        o.raw("growth", r.growth ? growth_json(*r.growth) : "null");
        std::string speed = bench_rows_json(r.speed);
        while (!speed.empty() && speed.back() == '\n') speed.pop_back();
        o.raw("speed", speed);
    }));
    doc.close();
    return out + "\n";
}

std::string growth_plot_svg(std::span<const CompareRow> rows) {
    LogLogPlot plot;
    plot.title = "Build time against N" + (rows.empty() ? "" : " \u2014 " + rows.front().scene);
    plot.x_label = "triangles N";
    plot.y_label = "build time (ms, 1 thread)";
    for (const CompareRow& r : rows) {
        if (!r.growth) continue;
        PlotSeries s;
        s.name = r.accel;
        for (const GrowthPoint& p : r.growth->points) {
            s.x.push_back(double(p.n));
            s.y.push_back(p.build_ms);
        }
        plot.series.push_back(std::move(s));
    }
    return svg_log_log_plot(plot);
}

std::string speed_plot_svg(std::span<const CompareRow> rows, const CompareSettings& settings) {
    BarChart chart;
    chart.title = "Mrays/s" + (rows.empty() ? "" : " \u2014 " + rows.front().scene) + " (" +
                  std::to_string(settings.width) + "x" + std::to_string(settings.height) + ")";
    chart.y_label = "million rays per second";
    std::vector<const CompareRow*> pointers;
    for (const CompareRow& r : rows) pointers.push_back(&r);
    const std::vector<unsigned> threads = thread_counts(pointers);
    for (const char* set : kCompareSets)
        for (unsigned t : threads) chart.series.push_back(std::string(set) + ", " + thread_words(t));
    for (const CompareRow& r : rows) {
        BarGroup g;
        g.label = r.accel;
        for (const char* set : kCompareSets)
            for (unsigned t : threads) {
                const BenchRow* b = r.find(set, t);
                g.values.push_back(b ? b->mrays : NAN);
            }
        chart.groups.push_back(std::move(g));
    }
    return svg_bar_chart(chart);
}

}  // namespace thicket
