#include "thicket/bench/bench_tables.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

#include "thicket/bench/agreement.h"
#include "thicket/bench/number_text.h"
#include "thicket/bench/text_table.h"

namespace thicket {

namespace {

using Align = TextTable::Align;

std::string fixed3(double v) { return three_digits(v, "-"); }

std::string ratio_text(double r) { return r < 0.01 ? "<0.01x" : printf_string("%.2fx", r); }

std::string bytes_text(double bytes) {
    static const char* const units[] = {"B", "KiB", "MiB", "GiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 3) {
        bytes /= 1024.0;
        ++u;
    }
    return printf_string(u == 0 ? "%.0f" : "%.1f", bytes) + " " + units[u];
}

std::string agree_text(const BenchRow& r) {
    if (!r.agree) return "-";
    const std::string settled = r.arbitrated ? " [" + grouped(r.arbitrated) + "]" : "";
    if (r.disagreeing == 0) return "100" + settled;
    // Never round a disagreement up to "100".
    const double shown = std::min(*r.agree, 99.999);
    return printf_string(shown >= 99.0 ? "%.3f" : "%.2f", shown) + " (" + grouped(r.disagreeing) + ")" + settled;
}

std::string speed_text(const BenchRow& r) {
    std::string s = fixed3(r.mrays) + " (" + fixed3(r.mrays_min) + "-" + fixed3(r.mrays_max) + ")";
    if (r.cpu_util < kDisturbedUtilization) s += "!";
    return s;
}

struct SceneRows {
    std::string scene;
    std::vector<const BenchRow*> rows;
};

std::vector<SceneRows> by_scene(std::span<const BenchRow> rows) {
    std::vector<SceneRows> out;
    for (const BenchRow& r : rows) {
        auto it = std::find_if(out.begin(), out.end(), [&](const SceneRows& s) { return s.scene == r.scene; });
        if (it == out.end()) {
            out.push_back({r.scene, {}});
            it = out.end() - 1;
        }
        it->rows.push_back(&r);
    }
    return out;
}

template <class T>
void add_unique(std::vector<T>& v, const T& x) {
    if (std::find(v.begin(), v.end(), x) == v.end()) v.push_back(x);
}

std::string render(const TextTable& t, TableStyle style) {
    return style == TableStyle::Markdown ? t.markdown() : t.terminal();
}

std::string scene_section(const SceneRows& scene, TableStyle style) {
    std::vector<std::string> accels, sets;
    std::vector<unsigned> threads;
    std::map<std::string, size_t> set_rays;
    for (const BenchRow* r : scene.rows) {
        add_unique(accels, r->accel);
        add_unique(sets, r->set);
        add_unique(threads, r->threads);
        set_rays[r->set] = r->set_rays;
    }
    std::sort(threads.begin(), threads.end());
    const BenchRow& first = *scene.rows.front();
    const bool md = style == TableStyle::Markdown;

    std::string out;
    std::string rays_text;
    for (const std::string& s : sets) rays_text += (rays_text.empty() ? "" : ", ") + s + " " + grouped(set_rays[s]);
    std::string threads_text;
    for (unsigned t : threads) threads_text += (threads_text.empty() ? "" : " and ") + std::to_string(t);
    const std::string passes = std::to_string(first.reps) + " timed passes after a warm-up";
    const std::string timing =
        first.rounds > 1 ? "; median (slowest-fastest) over " + std::to_string(first.rounds) +
                               " rounds of the median of " + passes
                         : "; median (slowest-fastest) of " + passes;
    const std::string about = primitives_text(first.primitives, first.shapes) + "; rays: " + rays_text + timing + ", on " +
                              threads_text + " thread" + (threads.size() > 1 || threads[0] > 1 ? "s" : "");
    out += md ? "### " + scene.scene + "\n\n" + about + ".\n\n" : "== " + scene.scene + ": " + about + "\n\n";

    // Structures: one line each.
    std::vector<std::string> head{"accel"};
    std::vector<Align> align{Align::Left};
    for (unsigned t : threads) {
        head.push_back("build " + std::to_string(t) + "t");
        align.push_back(Align::Right);
    }
    for (const char* h : {"memory", "B/prim", "nodes", "SAH cost"}) {
        head.push_back(h);
        align.push_back(Align::Right);
    }
    TextTable structures(head, align);
    bool serial_builds = false;
    for (const std::string& a : accels) {
        std::vector<std::string> cells{a};
        const BenchRow* any = nullptr;
        for (unsigned t : threads) {
            const auto it = std::find_if(scene.rows.begin(), scene.rows.end(),
                                         [&](const BenchRow* r) { return r->accel == a && r->threads == t; });
            if (it == scene.rows.end()) {
                cells.push_back("-");
                continue;
            }
            any = *it;
            const bool mark = !(*it)->build_parallel && threads.size() > 1;
            serial_builds |= mark;
            cells.push_back(printf_string("%.1f ms", (*it)->build_ms) + (mark ? "*" : ""));
        }
        cells.push_back(any ? bytes_text(double(any->bytes)) : "-");
        cells.push_back(any ? printf_string("%.1f", any->bytes_per_primitive()) : "-");
        cells.push_back(any && any->nodes ? grouped(any->nodes) : "-");
        cells.push_back(any && any->sah_cost > 0 ? printf_string("%.2f", any->sah_cost) : "-");
        structures.add_row(cells);
    }
    out += render(structures, style) + "\n";

    // Speed: one line per structure and set, one column group per thread count.
    head = {"accel", "set"};
    align = {Align::Left, Align::Left};
    bool have_ratio = false, have_agree = false, sampled = false, disturbed = false;
    for (const BenchRow* r : scene.rows) {
        have_ratio |= r->ratio.has_value();
        have_agree |= r->agree.has_value();
        disturbed |= r->cpu_util < kDisturbedUtilization;
    }
    for (unsigned t : threads) {
        head.push_back("Mrays/s " + std::to_string(t) + "t");
        align.push_back(Align::Right);
        if (have_ratio) {
            head.push_back("x emb " + std::to_string(t) + "t");
            align.push_back(Align::Right);
        }
    }
    for (const char* h : {"nodes/ray", "prims/ray", "hit %", "agree %", "max dt rel"}) {
        head.push_back(h);
        align.push_back(Align::Right);
    }
    TextTable speed(head, align);
    for (const std::string& a : accels) {
        bool first_line = true;
        for (const std::string& s : sets) {
            std::vector<const BenchRow*> cols;
            for (unsigned t : threads) {
                const auto it = std::find_if(scene.rows.begin(), scene.rows.end(), [&](const BenchRow* r) {
                    return r->accel == a && r->set == s && r->threads == t;
                });
                cols.push_back(it == scene.rows.end() ? nullptr : *it);
            }
            const BenchRow* any = nullptr;
            for (const BenchRow* c : cols) any = any ? any : c;
            if (!any) continue;
            std::string set_cell = s;
            if (any->stride > 1) {
                set_cell += " 1/" + std::to_string(any->stride);
                sampled = true;
            }
            std::vector<std::string> cells{md || first_line ? a : "", set_cell};
            first_line = false;
            for (const BenchRow* c : cols) {
                cells.push_back(c ? speed_text(*c) : "-");
                if (have_ratio) cells.push_back(c && c->ratio ? ratio_text(*c->ratio) : "-");
            }
            cells.push_back(any->nodes_per_ray ? fixed3(*any->nodes_per_ray) : "-");
            cells.push_back(any->prims_per_ray ? fixed3(*any->prims_per_ray) : "-");
            cells.push_back(printf_string("%.1f", 100.0 * any->hit_rate));
            cells.push_back(agree_text(*any));
            const std::optional<double>& dt = any->max_dt_rel;
            cells.push_back(!dt ? "-" : *dt == 0.0 ? "0" : printf_string("%.1e", *dt));
            speed.add_row(cells);
        }
    }
    out += render(speed, style);

    // Children entered per interior node visit, where a counting pass reported them (bvh8).
    using A = TextTable::Align;
    TextTable entered({"accel", "set", "0", "1", "2", "3", "4", "5+"}, {A::Left, A::Left, A::Right, A::Right, A::Right, A::Right, A::Right, A::Right});
    for (const std::string& a : accels)
        for (const std::string& s : sets) {
            const auto it = std::find_if(scene.rows.begin(), scene.rows.end(), [&](const BenchRow* r) {
                return r->accel == a && r->set == s && !r->entered_share.empty();
            });
            if (it == scene.rows.end()) continue;
            std::vector<std::string> cells{a, s};
            for (double share : (*it)->entered_share) cells.push_back(printf_string("%.1f%%", 100.0 * share));
            entered.add_row(cells);
        }
    if (entered.rows()) out += "\nchildren entered per interior node visit (counting pass), % of visits\n\n" + render(entered, style);

    std::vector<std::string> notes;
    if (serial_builds)
        notes.push_back("*: single-threaded builder; its one build is reported for every thread count.");
    if (sampled)
        notes.push_back("1/k: timed on every k-th ray of the set (about a tenth of the pass budget per pass), "
                        "because a single-thread pass over the whole set was estimated to take longer than the "
                        "pass budget (--pass-budget).");
    if (disturbed)
        notes.push_back("!: other work on the machine took CPU time from these passes (below " +
                        printf_string("%.0f", 100.0 * kDisturbedUtilization) + "% of the CPU time the threads "
                        "could use, in the best of the attempts made): the figure is too low.");
    if (have_ratio)
        notes.push_back("x emb: Mrays/s as a multiple of embree-high's on the same rays and threads: the median "
                        "over passes timed in pairs with embree-high's, so that both are timed under the same "
                        "machine conditions.");
    if (have_agree)
        notes.push_back("agree: % of rays answered like embree-high (same miss, same primitive, or same t within " +
                        printf_string("%g", kTieTolerance) + " relative; any-hit: same flag), the number that "
                        "differ in parentheses; in brackets, rays whose answers differ but double-precision "
                        "arithmetic shows both answers possible within float rounding of this ray (a ray at the "
                        "mesh's outer edge: README, \"How thicket bench counts agreement\"), counted as agreeing; "
                        "max dt rel: largest "
                        "relative t difference among the rays that agree by the first rule and hit.");
    else
        notes.push_back("agree: no Embree reference in this run, so no ray-for-ray comparison.");
    out += "\n";
    for (const std::string& n : notes) out += (md ? "- " : "  ") + n + "\n";
    return out;
}

}  // namespace

std::string format_bench_tables(std::span<const BenchRow> rows, TableStyle style) {
    std::string out;
    for (const SceneRows& s : by_scene(rows)) {
        if (!out.empty()) out += '\n';
        out += scene_section(s, style);
    }
    return out;
}

BenchNoise bench_noise(std::span<const BenchRow> rows) {
    BenchNoise n;
    std::vector<double> spreads;
    for (const BenchRow& r : rows) {
        if (!(r.mrays > 0)) continue;
        n.retried += r.attempts > 1;
        n.disturbed += r.cpu_util < kDisturbedUtilization;
        const double spread = 100.0 * (r.mrays_max - r.mrays_min) / r.mrays;
        spreads.push_back(spread);
        if (spread >= n.max_spread) {
            n.max_spread = spread;
            n.max_row = r.scene + " " + r.accel + " " + r.set + " " + std::to_string(r.threads) + "t";
        }
    }
    n.rows = spreads.size();
    if (spreads.empty()) return n;
    std::sort(spreads.begin(), spreads.end());
    n.median_spread = spreads[spreads.size() / 2];
    n.p90_spread = spreads[std::min(spreads.size() - 1, size_t(0.9 * double(spreads.size())))];
    return n;
}

std::string format_bench_noise(std::span<const BenchRow> rows) {
    const BenchNoise n = bench_noise(rows);
    if (n.rows == 0) return "noise: no timed rows";
    const bool rounds = std::any_of(rows.begin(), rows.end(), [](const BenchRow& r) { return r.rounds > 1; });
    char buf[768];
    std::snprintf(buf, sizeof buf,
                  "noise: spread of the %s, (fastest - slowest) / median, over %zu rows: median %.1f%%, "
                  "90th percentile %.1f%%, largest %.1f%% (%s); %zu rows timed again because other work took CPU "
                  "time from them, %zu still disturbed (marked !)",
                  rounds ? "round medians (run-to-run)" : "timed passes", n.rows, n.median_spread, n.p90_spread,
                  n.max_spread, n.max_row.c_str(), n.retried, n.disturbed);
    return buf;
}

}  // namespace thicket
