// `thicket compare`: the lecture's comparison table of acceleration structures, measured: one row
// per structure with its partitioning, build-time growth exponent, memory, SAH cost, work per ray
// and Mrays/s, plus SVG charts of build time against N and of Mrays/s.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <set>

#include <unistd.h>

#include "bench_commands.h"
#include "thicket/bench/compare_report.h"
#include "thicket/bench/runner.h"
#include "thicket/bench/scene_sizes.h"
#include "thicket/core/error.h"
#include "thicket/util/atomic_file.h"
#include "thicket/util/parallel.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

namespace {

namespace fs = std::filesystem;

struct CompareArgs {
    std::vector<std::string> scenes;
    std::vector<std::string> accels;
    std::string sizes;
    size_t max_size = kDefaultMaxGrowthSize;
    size_t fit_min = kDefaultFitMinSize;
    int build_reps = 5;
    double build_budget_s = 60.0;
    bool no_growth = false;
    std::string size = "320x240";
    std::string camera;
    int reps = 5;
    unsigned threads = 0;
    double pass_budget_ms = 1000.0;
    std::string json;
    bool markdown = false;
    std::string plot_dir = "compare-plots";
    bool no_plots = false;
    bool force = false;
};

// A file-name stem for a scene's plots: its file's stem, unusual characters replaced.
std::string plot_stem(const std::string& path) {
    std::string stem = fs::path(path).stem().string();
    for (char& c : stem)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    return stem.empty() ? "scene" : stem;
}

struct PlotFiles {
    std::string growth, speed;  // empty: not written
};

// The plot files of every scene, named before any slow work so that a clash is reported at once.
std::vector<PlotFiles> plot_files(const CompareArgs& args) {
    std::vector<PlotFiles> files;
    std::set<std::string> used;
    for (const std::string& scene : args.scenes) {
        PlotFiles f;
        if (!args.no_plots) {
            std::string stem = plot_stem(scene);
            for (int k = 2; used.count(stem); ++k) stem = plot_stem(scene) + "-" + std::to_string(k);
            used.insert(stem);
            const fs::path dir(args.plot_dir);
            if (!args.no_growth) f.growth = (dir / (stem + "-growth.svg")).string();
            f.speed = (dir / (stem + "-mrays.svg")).string();
        }
        files.push_back(f);
    }
    return files;
}

// Fails now, rather than after the measurements, when the charts could not be written: the
// directory (made only when the charts are written) must be one, or be creatable in a writable one.
void check_plot_dir(const std::string& dir) {
    std::error_code ec;
    fs::path p = fs::absolute(dir, ec);
    while (!ec && !fs::exists(p, ec) && p.has_parent_path() && p.parent_path() != p) p = p.parent_path();
    if (ec || !fs::is_directory(p, ec))
        throw Error("--plot-dir " + dir + ": " + p.string() + " is not a directory");
    if (access(p.c_str(), W_OK | X_OK) != 0)
        throw Error("--plot-dir " + dir + ": " + p.string() + " is not writable");
}

void write_output(const std::string& path, const std::string& bytes, const char* what) {
    if (path.empty()) return;
    const fs::path parent = fs::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty()) fs::create_directories(parent, ec);
    write_file_atomically(path, bytes);
    std::printf("wrote   %s (%s)\n", path.c_str(), what);
}

std::vector<std::string> compare_specs(const std::vector<std::string>& asked) {
    // Checked now: a typo fails before the first structure's minutes.
    const std::vector<std::string> specs = expand_accel_specs(asked.empty() ? default_compare_specs() : asked);
    if (specs.empty()) throw Error("no structure to compare (every registered one is brute force: name it with --accel)");
    return specs;
}

std::string sizes_text(const std::vector<size_t>& sizes) {
    std::string out;
    for (size_t n : sizes) {
        if (!out.empty()) out += ", ";
        out += size_label(n);
    }
    return out;
}

CompareRow compare_one(const Scene& scene, const std::string& label, const std::string& spec,
                       const std::vector<Scene>& sized, const std::vector<RaySet>& sets, const CompareArgs& args,
                       const CompareSettings& settings, const BenchOptions& options) {
    CompareRow row;
    row.scene = label;
    row.primitives = scene.primitive_count();
    row.shapes = scene.shapes.size();
    row.accel = spec;
    const AccelSpec parsed = parse_accel_spec(spec);
    row.spec = parsed.str();
    row.partitioning = parsed.info ? parsed.info->partitioning : Partitioning::Unknown;

    if (!args.no_growth) {
        Progress progress("growth " + spec, sized.size(), "sizes");
        try {
            row.growth = measure_growth(spec, sized, settings.growth, [&](const GrowthPoint&) { progress.advance(); });
        } catch (...) {
            progress.abandon();
            throw;
        }
        progress.finish();
        const Growth& g = *row.growth;
        std::string line = "growth  " + spec + ": " + std::to_string(g.points.size()) + " sizes in " +
                           format_duration(progress.elapsed());
        char buf[96];
        if (g.fit.valid()) {
            std::snprintf(buf, sizeof buf, ", build ms ~ N^%.2f over %s-%s", g.fit.exponent,
                          size_label(size_t(g.fit.min_n)).c_str(), size_label(size_t(g.fit.max_n)).c_str());
            line += buf;
        }
        if (g.stopped_at) {
            std::snprintf(buf, sizeof buf, "; stopped before N=%s (predicted %.0f s)",
                          size_label(*g.stopped_at).c_str(), g.predicted_s);
            line += buf;
        }
        std::fprintf(stderr, "%s\n", line.c_str());
    }

    const TracerFactory factory = accel_tracer_factory(spec, parsed);
    Progress progress("speed " + spec, bench_steps(1, sets.size(), options), "steps");
    BenchCallbacks callbacks;
    callbacks.advance = [&](uint64_t n) { progress.advance(n); };
    try {
        row.speed = bench_scene(scene, label, std::span<const TracerFactory>(&factory, 1), sets, options, callbacks);
    } catch (...) {
        progress.abandon();
        throw;
    }
    progress.finish();
    std::string line = "speed   " + spec + ": built in " + format_duration(row.build_ms() / 1000);
    for (const BenchRow& b : row.speed) {
        char buf[96];
        std::snprintf(buf, sizeof buf, ", %s %ut %.3g Mrays/s", b.set.c_str(), b.threads, b.mrays);
        line += buf;
    }
    std::fprintf(stderr, "%s\n", line.c_str());
    return row;
}

int run_compare(const CompareArgs& args) {
    // Every option is checked before the slow work, so a typo costs nothing.
    const std::vector<std::string> specs = compare_specs(args.accels);
    CompareSettings settings;
    RaySetOptions ray_options;
    parse_ray_set_size(args.size, ray_options);
    if (!args.camera.empty()) ray_options.camera = parse_camera(args.camera);
    settings.width = ray_options.width;
    settings.height = ray_options.height;
    if (args.reps < 1 || args.reps > kMaxReps)
        throw Error("--reps " + std::to_string(args.reps) + ": must be between 1 and " + std::to_string(kMaxReps) +
                    " (5 or more for a trustworthy median)");
    if (args.build_reps < 1 || args.build_reps > kMaxReps)
        throw Error("--build-reps " + std::to_string(args.build_reps) + ": must be between 1 and " + std::to_string(kMaxReps));
    if (args.max_size < 1 || args.max_size > kMaxSceneSize)
        throw Error("--max-size " + std::to_string(args.max_size) + " must be from 1 to " + std::to_string(kMaxSceneSize));
    if (!(args.pass_budget_ms >= 0.0)) throw Error("--pass-budget must be a non-negative number of milliseconds");
    if (!(args.build_budget_s >= 0.0)) throw Error("--build-budget must be a non-negative number of seconds");
    settings.reps = args.reps;
    settings.growth_measured = !args.no_growth;
    settings.growth.max_builds = args.build_reps;
    settings.growth.build_budget_s = args.build_budget_s;
    settings.growth.fit_min_size = double(args.fit_min);
    if (args.sizes.empty()) {
        settings.growth.sizes = default_growth_sizes(args.max_size);
    } else {
        settings.growth.sizes = parse_size_list(args.sizes);
        std::erase_if(settings.growth.sizes, [&](size_t n) { return n > args.max_size; });
        if (settings.growth.sizes.empty())
            throw Error("every size of --sizes " + args.sizes + " is above --max-size " + std::to_string(args.max_size));
    }

    const std::vector<PlotFiles> plots = plot_files(args);
    for (const PlotFiles& f : plots) {
        refuse_overwrite(f.growth, args.force);
        refuse_overwrite(f.speed, args.force);
    }
    refuse_output_is_input(args.json, args.scenes);
    for (const PlotFiles& f : plots) {
        refuse_output_is_input(f.growth, args.scenes);
        refuse_output_is_input(f.speed, args.scenes);
    }
    refuse_overwrite(args.json, args.force);
    if (!args.no_plots) check_plot_dir(args.plot_dir);

    BenchOptions options;
    options.reps = args.reps;
    options.threads = args.threads;
    options.pass_budget_ms = args.pass_budget_ms;
    std::string names;
    for (const std::string& s : specs) {
        if (!names.empty()) names += ", ";
        names += s;
    }
    std::printf("machine %u hardware threads; load average %s before the run\n", resolve_threads(0),
                load_average().c_str());
    std::printf("compare %zu structures: %s\n", specs.size(), names.c_str());
    if (args.no_growth)
        std::printf("growth  not measured (--no-growth)\n");
    else
        std::printf("growth  build time on 1 thread at N = %s triangles; exponent fitted over N >= %s\n",
                    sizes_text(settings.growth.sizes).c_str(), size_label(args.fit_min).c_str());
    const std::vector<unsigned> thread_counts = bench_thread_counts(args.threads);
    std::printf("speed   primary and diffuse rays, %dx%d, median of %d timed passes after a warm-up, on %s\n",
                ray_options.width, ray_options.height, args.reps,
                thread_counts.size() > 1 ? ("1 and " + std::to_string(thread_counts.back()) + " threads").c_str()
                                         : "1 thread");
    std::fflush(stdout);

    std::vector<CompareRow> all_rows;
    for (size_t si = 0; si < args.scenes.size(); ++si) {
        const std::string& path = args.scenes[si];
        const std::string label = scene_label(path);
        const Scene scene = load_scene_verbose(path);
        std::vector<RaySet> sets;
        {
            const std::unique_ptr<Accel> hits_from = build_accel(kRaySetHitSpec, scene);
            const RaySetView view = ray_set_view(scene, *hits_from, ray_options);
            print_view(view, !args.camera.empty());
            const std::vector<std::string> set_names(std::begin(kCompareSets), std::end(kCompareSets));
            sets = generate_ray_sets(scene, *hits_from, view, set_names, ray_options, args.threads);
        }
        std::printf("rays    primary %zu, diffuse %zu\n", sets[0].rays.size(), sets[1].rays.size());
        std::fflush(stdout);

        std::vector<Scene> sized;
        if (!args.no_growth) {
            for (size_t n : settings.growth.sizes) sized.push_back(scene_of_size(scene, n));
            const size_t triangles = scene.mesh.triangle_count();
            const int rounds = subdivision_rounds(triangles, settings.growth.sizes.back());
            if (scene.has_shapes())
                std::fprintf(stderr, "sizes   %s: made of its %zu triangles; its %zu shapes are left out\n", label.c_str(),
                             triangles, scene.shapes.size());
            std::fprintf(stderr, "sizes   %s: %s%s\n", label.c_str(), sizes_text(settings.growth.sizes).c_str(),
                         rounds ? (" (above " + size_label(triangles) +
                                   ": from the triangles split into four, up to " + std::to_string(rounds) +
                                   (rounds == 1 ? " time)" : " times)"))
                                      .c_str()
                                : "");
        }

        std::vector<CompareRow> rows;
        for (const std::string& spec : specs)
            rows.push_back(compare_one(scene, label, spec, sized, sets, args, settings, options));

        const TableStyle style = args.markdown ? TableStyle::Markdown : TableStyle::Terminal;
        std::printf("\n%s\n", format_compare_tables(rows, settings, style).c_str());
        write_output(plots[si].growth, growth_plot_svg(rows), "build time against N");
        write_output(plots[si].speed, speed_plot_svg(rows, settings), "Mrays/s per structure");
        std::fflush(stdout);
        all_rows.insert(all_rows.end(), rows.begin(), rows.end());
    }
    std::printf("machine load average %s after the run\n", load_average().c_str());
    write_output(args.json, compare_json(all_rows, settings), (std::to_string(all_rows.size()) + " rows").c_str());
    return 0;
}

}  // namespace

Command add_compare_command(CLI::App& app) {
    auto args = std::make_shared<CompareArgs>();
    CLI::App* cmd = app.add_subcommand(
        "compare", "the lecture's comparison table of acceleration structures, measured on each SCENE, with charts");
    cmd->footer(
        "One row per structure: partitioning (object or space), build time and its growth exponent k (build ms ~ "
        "N^k, fitted over scenes of N triangles made from the scene: a random subset of its triangles, fixed "
        "seed, or when it has fewer than N, of its triangles split into four by their edge midpoints as often "
        "as needed), memory per triangle, SAH cost, nodes visited and primitives tested per ray, and Mrays/s on "
        "the primary and diffuse rays of `thicket rays` with the timing of `thicket bench`. Builds run on 1 "
        "thread. Charts go to --plot-dir: SCENE-growth.svg (build time against N, log-log) and SCENE-mrays.svg. "
        "Existing files are never overwritten without --force.");
    cmd->add_option("SCENE", args->scenes, scene_help())->required()->type_name("SCENE...");
    add_flatten_option(cmd);
    cmd->add_option("-a,--accel", args->accels,
                    "structure spec to compare (repeatable); default: every registered structure with its default "
                    "options except brute force (name `brute` to include it: it is timed on a sample of the rays); `all` = "
                    "every registered variant (`thicket accels`)")
        ->type_name("SPEC");
    cmd->add_option("--sizes", args->sizes,
                    "comma-separated triangle counts of the growth sweep, e.g. 1000,1e4,1e5 (default: 1k, 3k, 10k, "
                    "30k, ... up to --max-size)")
        ->type_name("LIST");
    cmd->add_option("--max-size", args->max_size, "largest size of the growth sweep (caps --sizes too)")
        ->default_str("1000000")
        ->type_name("N");
    cmd->add_option("--fit-min", args->fit_min, "fit the growth exponent over sizes N >= this")
        ->default_str("10000")
        ->type_name("N");
    cmd->add_option("--build-reps", args->build_reps,
                    "builds per size: up to N, fewer once they took a second in all; the median is kept")
        ->default_str("5")
        ->type_name("N");
    cmd->add_option("--build-budget", args->build_budget_s,
                    "skip the sizes whose build is predicted to take longer than this (0: never skip)")
        ->default_str("60")
        ->type_name("SECONDS");
    cmd->add_flag("--no-growth", args->no_growth, "skip the growth sweep (no exponent, no growth chart)");
    cmd->add_option("-s,--size", args->size, "image size of the primary rays")
        ->default_str("320x240")
        ->type_name("WxH");
    cmd->add_option("-c,--camera", args->camera,
                    "camera for every scene: position and target (and vertical fov in degrees, default 45); up is +y")
        ->type_name("px,py,pz,tx,ty,tz[,fov]");
    cmd->add_option("--reps", args->reps, "timed passes per figure, after one warm-up pass")
        ->default_str("5")
        ->type_name("N");
    add_threads_option(cmd, args->threads);
    cmd->add_option("--pass-budget", args->pass_budget_ms,
                    "milliseconds a single-thread pass may take; a slower structure is timed on every k-th ray "
                    "(0: never sample)")
        ->default_str("1000")
        ->type_name("MS");
    cmd->add_option("--json", args->json, "also write every row as JSON to FILE")->type_name("FILE");
    cmd->add_flag("--markdown", args->markdown, "print the tables as Markdown");
    cmd->add_option("--plot-dir", args->plot_dir, "directory for the SVG charts (created if missing)")
        ->default_str("compare-plots")
        ->type_name("DIR");
    cmd->add_flag("--no-plots", args->no_plots, "write no charts");
    cmd->add_flag("-f,--force", args->force, "overwrite existing chart and JSON files");
    return {cmd, [args] { return run_compare(*args); }};
}

}  // namespace thicket::cli
