// `thicket bench`: every structure asked for (and Embree, when built with it) on the standard ray
// sets of each scene, same rays, same timing loop, each answer checked against Embree-high.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "bench_commands.h"
#include "bench_precision.h"
#include "thicket/bench/animate.h"
#include "thicket/bench/bench_json.h"
#include "thicket/bench/bench_tables.h"
#include "thicket/bench/runner.h"
#include "thicket/query/ray_rows.h"
#include "thicket/core/error.h"
#include "thicket/util/atomic_file.h"
#include "thicket/util/input_file.h"
#include "thicket/util/npy.h"
#include "thicket/util/parallel.h"
#include "thicket/util/progress.h"

#if THICKET_HAVE_EMBREE
#include "embree_tracer.h"
#include "embree_tree.h"
#endif

namespace thicket::cli {

namespace {

struct BenchArgs {
    std::vector<std::string> scenes;
    std::vector<std::string> accels;
    std::string sets = "primary,shadow,diffuse,random";
    bool sets_given = false;
    std::vector<std::string> ray_files;      // --rays: the user's own rays, closest hit
    std::vector<std::string> any_ray_files;  // --any-rays: the user's own rays, any hit
    std::string size = "320x240";
    std::string camera;
    int reps = 5;
    int rounds = 1;
    unsigned threads = 0;
    double pass_budget_ms = 1000.0;
    std::string json;
    bool force = false;
    bool markdown = false;
    bool no_embree = false;
    int animate = 0;  // frames; 0: the standard bench
    std::string motion = "bend";
    bool motion_given = false;
    bool reps_given = false;
    double offset = 0.0;  // --offset: the precision=double figures instead (bench_precision.h)
    bool offset_given = false;
};

// A tracer of every spec asked for (parse_accel_specs(): `all` expanded, duplicates dropped,
// each checked before any slow work). With Embree linked, bvh8:tree=embree-* can build.
std::vector<TracerFactory> thicket_tracers(const std::vector<AskedSpec>& specs) {
#if THICKET_HAVE_EMBREE
    install_embree_tree_builder();
#endif
    std::vector<TracerFactory> out;
    for (const AskedSpec& s : specs) out.push_back(accel_tracer_factory(s.text, s.spec));
    return out;
}

void print_machine(const char* when) {
    std::printf("machine %u hardware threads; load average %s %s the run\n", resolve_threads(0),
                load_average().c_str(), when);
}

/// The rays of a .npy file (N x 8 float32, `thicket trace`'s layout) as a set of their own, read
/// through the rows path that `thicket trace` and the Python module use (query/ray_rows.h): the
/// same rows are the same rays everywhere, and a row without a meaning is left out (said here).
RaySet file_ray_set(const std::string& path, bool any_hit, unsigned threads) {
    const NpyFloatArray matrix = read_npy_matrix(path, 8);
    const size_t n = matrix.shape[0];
    RayBatch batch = make_rays(RayRows{matrix.values.data(), n, 8}, threads);
    if (batch.rays.empty()) throw Error(path + ": no row of its " + std::to_string(n) + " is a ray to trace");
    if (batch.compacted)
        std::printf("rays    %s: %zu of %zu rows are not rays (non-finite, zero direction or empty interval): left out\n",
                    path.c_str(), n - batch.rays.size(), n);
    RaySet set;
    set.name = std::filesystem::path(path).filename().string() + (any_hit ? " (any hit)" : "");
    set.any_hit = any_hit;
    set.rays = std::move(batch.rays);
    return set;  // not marked coherent: nothing is known of their order
}

/// `--animate FRAMES`: refit against rebuild, frame by frame (bench/animate.h).
int run_animate(const BenchArgs& args) {
    AnimateOptions options;
    options.frames = args.animate;
    options.motion = parse_animate_motion(args.motion);
    options.reps = args.reps_given ? args.reps : 3;
    options.threads = args.threads;
    if (options.reps < 1 || options.reps > kMaxReps)
        throw Error("--reps " + std::to_string(options.reps) + ": must be between 1 and " + std::to_string(kMaxReps));
    const std::pair<const char*, bool> others[] = {{"--rays", !args.ray_files.empty()},
                                                   {"--any-rays", !args.any_ray_files.empty()},
                                                   {"--json", !args.json.empty()},
                                                   {"--rounds", args.rounds != 1},
                                                   {"--markdown", args.markdown}};
    for (const auto& [option, given] : others)
        if (given) throw Error(std::string(option) + " does not go with --animate (it measures the standard bench)");
    options.sets = parse_ray_set_list(args.sets_given ? args.sets : std::string("primary"));
    parse_ray_set_size(args.size, options.rays);
    if (!args.camera.empty()) options.rays.camera = parse_camera(args.camera);
    const std::vector<AskedSpec> specs =
        parse_accel_specs(args.accels.empty() ? std::vector<std::string>{kDefaultSpec} : args.accels);
    std::vector<TracerFactory> tracers = thicket_tracers(specs);
    std::string embree_note = "Embree left out (--no-embree)";
#if THICKET_HAVE_EMBREE
    if (!args.no_embree) {
        tracers.push_back(embree_tracer_factory(EmbreeQuality::Refit));
        embree_note = "embree-refit: Embree " + embree_version() +
                      ", scene quality low (two-level) with the geometry at RTC_BUILD_QUALITY_REFIT";
    }
#else
    if (!args.no_embree) embree_note = "Embree left out: this thicket was built without it";
#endif
    print_machine("before");
    std::printf("embree  %s\n", embree_note.c_str());
    for (const std::string& path : args.scenes) {
        const Scene rest = load_scene_verbose(path);
        std::vector<TracerFactory> scene_tracers = tracers;
        if (rest.has_shapes())
            std::erase_if(scene_tracers, [](const TracerFactory& t) { return t.name == "embree-refit"; });
        std::printf("animate %s: %d frames, motion %s, sets %s, %s, median of %d timed refits, builds and "
                    "passes per frame\n",
                    scene_label(path).c_str(), options.frames, animate_motion_name(options.motion),
                    (args.sets_given ? args.sets : std::string("primary")).c_str(), args.size.c_str(), options.reps);
        std::printf("%s\n", animate_header().c_str());
        std::fflush(stdout);
        const std::vector<AnimateRow> rows = animate_scene(rest, scene_tracers, options, [](const AnimateRow& r) {
            std::printf("%s\n", format_animate_row(r).c_str());
            std::fflush(stdout);
        });
        std::printf("%s", format_animate_summary(rows).c_str());
    }
    std::printf("advice  rebuild instead of refitting once 'SAH x' passes about 1.3 or 'Mr/s x' falls below "
                "about 0.8 (README.md, \"Moving vertices: refit\")\n");
    print_machine("after");
    return 0;
}

int run_bench(const BenchArgs& args) {
    if (args.animate != 0) return run_animate(args);
    if (args.offset_given) return run_precision_bench(args.scenes, args.offset, args.reps, args.threads);
    if (args.motion_given) throw Error("--motion goes with --animate (the motion of an animated sequence)");
    // Check every option before the slow work, so a typo costs nothing.
    const bool own_rays = !args.ray_files.empty() || !args.any_ray_files.empty();
    if (own_rays && args.scenes.size() > 1)
        throw Error("--rays/--any-rays: rays from a file belong to one scene; give one SCENE (got " +
                    std::to_string(args.scenes.size()) + ")");
    // With rays of their own the standard sets run only when asked for.
    const std::vector<std::string> set_names =
        own_rays && !args.sets_given ? std::vector<std::string>{} : parse_ray_set_list(args.sets);
    for (const std::string& f : args.ray_files) check_regular_input(f, "--rays file");
    for (const std::string& f : args.any_ray_files) check_regular_input(f, "--any-rays file");
    RaySetOptions ray_options;
    parse_ray_set_size(args.size, ray_options);
    if (!args.camera.empty()) ray_options.camera = parse_camera(args.camera);
    // Upper limits bound the run: 2e9 passes of 10^5 rays would run for years, silently.
    if (args.reps < 1 || args.reps > kMaxReps)
        throw Error("--reps " + std::to_string(args.reps) + ": must be between 1 and " + std::to_string(kMaxReps) +
                    " (5 or more for a trustworthy median)");
    if (args.rounds < 1 || args.rounds > kMaxRounds)
        throw Error("--rounds " + std::to_string(args.rounds) + ": must be between 1 and " + std::to_string(kMaxRounds));
    if (!(args.pass_budget_ms >= 0.0)) throw Error("--pass-budget must be a non-negative number of milliseconds");
    std::vector<std::string> inputs = args.scenes;
    inputs.insert(inputs.end(), args.ray_files.begin(), args.ray_files.end());
    inputs.insert(inputs.end(), args.any_ray_files.begin(), args.any_ray_files.end());
    refuse_output_is_input(args.json, inputs);
    refuse_overwrite(args.json, args.force);
    const std::vector<AskedSpec> specs =
        parse_accel_specs(args.accels.empty() ? std::vector<std::string>{"bvh"} : args.accels);
    std::vector<TracerFactory> tracers = thicket_tracers(specs);

    std::string embree_note;
#if THICKET_HAVE_EMBREE
    if (args.no_embree) {
        embree_note = "comparison off (--no-embree): no Embree rows, no ratios, no agreement";
    } else {
        tracers.insert(tracers.begin(), {embree_tracer_factory(EmbreeQuality::High),
                                         embree_tracer_factory(EmbreeQuality::Medium)});
        embree_note = "Embree " + embree_version() + " at build quality high (the reference) and medium";
    }
#else
    embree_note = args.no_embree ? "comparison off (--no-embree): no Embree rows, no ratios, no agreement"
                                 : "comparison off: this thicket was built without Embree (install libembree-dev "
                                   "and rebuild); no Embree rows, no ratios, no agreement";
#endif

    BenchOptions options;
    options.reps = args.reps;
    options.threads = args.threads;
    options.pass_budget_ms = args.pass_budget_ms;
    const std::vector<unsigned> thread_counts = bench_thread_counts(args.threads);
    print_machine("before");
    std::printf("embree  %s\n", embree_note.c_str());
    // Structures whose kernels are chosen at run time (bvh8's ISA): say which ones this run measures.
    for (const AskedSpec& s : specs)
        if (s.spec.info->kernels)
            std::printf("isa     %s runs the %s kernels\n", s.text.c_str(), s.spec.info->kernels(s.spec).c_str());
    const size_t set_count = set_names.size() + args.ray_files.size() + args.any_ray_files.size();
    const std::string size_text =
        set_names.empty() ? "" : ", " + std::to_string(ray_options.width) + "x" + std::to_string(ray_options.height);
    std::printf("bench   %zu tracers x %zu ray sets%s, median of %d timed passes after a warm-up%s, on %s\n",
                tracers.size(), set_count, size_text.c_str(), args.reps,
                args.rounds > 1 ? (", " + std::to_string(args.rounds) + " rounds").c_str() : "",
                thread_counts.size() > 1 ? ("1 and " + std::to_string(thread_counts.back()) + " threads").c_str()
                                         : "1 thread");
    const bool with_embree = tracers.size() > 0 && tracers.front().name == kReferenceTracer;
    std::printf("build   built once per thread count by threaded builders (bvh, bvh8%s); the others (marked *) "
                "once, reported for every thread count\n", with_embree ? ", Embree" : "");
    std::fflush(stdout);

    std::vector<BenchRow> all_rows;
    for (const std::string& path : args.scenes) {
        const Scene scene = load_scene_verbose(path);
        const std::unique_ptr<Accel> hits_from = build_accel(kRaySetHitSpec, scene);
        std::vector<RaySet> sets;
        if (!set_names.empty()) {
            const RaySetView view = ray_set_view(scene, *hits_from, ray_options);
            print_view(view, !args.camera.empty());
            sets = generate_ray_sets(scene, *hits_from, view, set_names, ray_options, args.threads);
        }
        for (const std::string& f : args.ray_files) sets.push_back(file_ray_set(f, false, args.threads));
        for (const std::string& f : args.any_ray_files) sets.push_back(file_ray_set(f, true, args.threads));
        std::string counts;
        for (const RaySet& s : sets) {
            if (!counts.empty()) counts += ", ";
            counts += s.name + " " + std::to_string(s.rays.size());
        }
        std::printf("rays    %s\n", counts.c_str());
        std::fflush(stdout);

        // Embree holds the triangles only: on a scene with shapes it would answer other rays.
        std::vector<TracerFactory> scene_tracers = tracers;
        if (scene.has_shapes() && with_embree) {
            // Thicket's own tracers, one per spec, follow Embree's.
            scene_tracers.erase(scene_tracers.begin(), scene_tracers.end() - std::ptrdiff_t(specs.size()));
            std::printf("embree  left out for this scene: it has %zu shapes, and the Embree backend holds triangles "
                        "only (no ratios, no agreement)\n", scene.shapes.size());
        }
        const uint64_t steps = bench_steps(scene_tracers.size(), sets.size(), options) * uint64_t(args.rounds);
        Progress progress("bench " + scene_label(path), steps, "steps");
        BenchCallbacks callbacks;
        callbacks.advance = [&](uint64_t n) { progress.advance(n); };
        std::vector<std::vector<BenchRow>> rounds;
        try {
            for (int r = 0; r < args.rounds; ++r)
                rounds.push_back(bench_scene(scene, scene_label(path), scene_tracers, sets, options, callbacks));
        } catch (...) {
            progress.abandon();
            throw;
        }
        progress.finish();
        const std::vector<BenchRow> rows = merge_bench_rounds(rounds);
        const TableStyle style = args.markdown ? TableStyle::Markdown : TableStyle::Terminal;
        std::printf("\n%s\n", format_bench_tables(rows, style).c_str());
        std::fflush(stdout);
        all_rows.insert(all_rows.end(), rows.begin(), rows.end());
    }

    std::printf("%s%s\n", args.markdown ? "- " : "", format_bench_noise(all_rows).c_str());
    print_machine("after");
    if (!args.json.empty()) {
        write_file_atomically(args.json, bench_rows_json(all_rows));
        std::printf("wrote   %s (%zu rows)\n", args.json.c_str(), all_rows.size());
    }
    return 0;
}

}  // namespace

Command add_bench_command(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    CLI::App* cmd = app.add_subcommand(
        "bench", "measure structures (and Embree) on standard ray sets of each SCENE: speed, build, memory, agreement");
    cmd->footer(
        "For every structure and ray set: Mrays/s on 1 thread and on all threads (median, slowest and fastest of "
        "--reps timed passes after a warm-up), the ratio to embree-high on the same rays, nodes visited and "
        "primitives tested per ray (a separate untimed pass), build time, memory, SAH cost, and agreement with "
        "embree-high ray for ray. Ray sets are those of `thicket rays` (see its --help). A structure whose pass "
        "over a set would take longer than --pass-budget on one thread is timed on every k-th ray (marked 1/k).\n"
        "Timings are only as quiet as the machine: the load average is printed before and after the run.\n"
        "THICKET_ISA=scalar|sse|avx2|avx512 caps bvh8's kernels and Embree's device alike (Embree's sse2 for "
        "scalar and sse), so that a capped run compares the same instruction sets.");
    cmd->add_option("SCENE", args->scenes, scene_help())->required()->type_name("SCENE...");
    add_flatten_option(cmd);
    cmd->add_option("-a,--accel", args->accels,
                    "structure spec to measure (repeatable); `all` = every registered variant (`thicket accels`); "
                    "default bvh")
        ->type_name("SPEC");
    cmd->add_option("--sets", args->sets,
                    "comma-separated ray sets: primary, shadow, diffuse, random (with --rays or --any-rays: none "
                    "unless given)")
        ->default_str("primary,shadow,diffuse,random")
        ->type_name("LIST")
        ->each([args](const std::string&) { args->sets_given = true; });
    cmd->add_option("--rays", args->ray_files,
                    "also measure your own rays, traced for the closest hit: a .npy float32 array (N, 8) of ox oy "
                    "oz dx dy dz tmin tmax, as `thicket trace` reads (repeatable; one SCENE)")
        ->type_name("FILE.npy");
    cmd->add_option("--any-rays", args->any_ray_files,
                    "the same, traced for any hit (occlusion), as the shadow set")
        ->type_name("FILE.npy");
    cmd->add_option("-s,--size", args->size, "image size of the primary set; random has WIDTH*HEIGHT rays")
        ->default_str("320x240")
        ->type_name("WxH");
    cmd->add_option("-c,--camera", args->camera,
                    "camera for every scene: position and target (and vertical fov in degrees, default 45); up is +y")
        ->type_name("px,py,pz,tx,ty,tz[,fov]");
    cmd->add_option("--reps", args->reps, "timed passes per figure, after one warm-up pass (1..1000; --animate: 3)")
        ->default_str("5")
        ->type_name("N")
        ->each([args](const std::string&) { args->reps_given = true; });
    cmd->add_option("--animate", args->animate,
                    "instead of the standard bench: move each SCENE's vertices over FRAMES frames (--motion) and "
                    "per frame print each structure's refit time against a rebuild's, SAH cost and Mrays/s after "
                    "refit against a rebuild's, and agreement; with Embree's refit (embree-refit) beside them. "
                    "Default structure bvh8; only refittable ones (bvh, bvh8, obb); sets default primary")
        ->type_name("FRAMES");
    cmd->add_option("--motion", args->motion,
                    "with --animate: bend (turned about the vertical axis, up to a quarter turn at the ends) or "
                    "explode (scaled up to 2x from the centre, vertices jittered by up to 5% of the size)")
        ->default_str("bend")
        ->type_name("bend|explode")
        ->each([args](const std::string&) { args->motion_given = true; });
    cmd->add_option("--rounds", args->rounds,
                    "repeat each scene's whole measurement N times and report the median round, with the "
                    "slowest and fastest round as the range: the honest spread on a shared machine")
        ->default_str("1")
        ->type_name("N");
    add_threads_option(cmd, args->threads);
    cmd->add_option("--pass-budget", args->pass_budget_ms,
                    "milliseconds a single-thread pass may take; a slower structure is timed on every k-th ray, "
                    "about a tenth of this per pass (0: never sample)")
        ->default_str("1000")
        ->type_name("MS");
    cmd->add_option("--json", args->json, "also write every row as JSON to FILE")->type_name("FILE");
    cmd->add_option("--offset", args->offset,
                    "instead of the standard bench, the precision=double figures: bvh:precision=double's time per "
                    "ray against the float bvh on the primary and diffuse sets (and the ratio), then, unless D is 0, "
                    "the scene moved by D on every axis (e.g. 1e7): how many rays the double and the float bvh answer "
                    "unlike double brute force")
        ->type_name("D")
        ->each([args](const std::string&) { args->offset_given = true; });
    cmd->add_flag("--markdown", args->markdown, "print the tables as Markdown");
    cmd->add_flag("--no-embree", args->no_embree, "leave Embree out (no ratios, no agreement)");
    cmd->add_flag("-f,--force", args->force, "overwrite the --json file if it exists");
    return {cmd, [args] { return run_bench(*args); }};
}

std::string scene_label(const std::string& path) {
    const std::filesystem::path p(path);
    return p.has_filename() && p.has_extension() ? p.filename().string() : path;
}

}  // namespace thicket::cli
