// `thicket trace`: closest-hit or any-hit queries for a batch of rays from a .npy file.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common.h"
#include "thicket/core/error.h"
#include "thicket/util/npy.h"
#include "thicket/util/parallel.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

namespace {

struct TraceArgs {
    std::string scene;
    AccelChoice accel;
    std::string rays;
    std::string output;
    bool any_hit = false;
    bool force = false;
    unsigned threads = 0;
};

int run_trace(const TraceArgs& args) {
    const std::optional<AccelSpec> spec = validate_accel_choice(args.accel);
    const std::string output = prepare_output(args.output, args.force, {args.scene, args.rays, args.accel.load});
    const NpyFloatArray rays = read_npy_matrix(args.rays, 8);
    const size_t n = rays.shape[0];
    std::printf("rays    %s: %zu rays\n", args.rays.c_str(), n);
    const Scene scene = load_scene_verbose(args.scene);
    const std::unique_ptr<Accel> accel = make_accel_verbose(args.accel, spec, scene);

    std::vector<Hit> hits(args.any_hit ? 0 : n);
    std::vector<uint8_t> occluded(args.any_hit ? n : 0);
    std::atomic<size_t> invalid{0}, found{0};
    Progress progress("trace", n, "rays");
    const auto start = std::chrono::steady_clock::now();
    // Small enough chunks that slow structures still move the progress bar, large enough that
    // fast ones do not contend on the work counter.
    const size_t grain = std::clamp<size_t>(n / (size_t(resolve_threads(args.threads)) * 64), 16, 4096);
    parallel_for(n, grain, args.threads, [&](size_t begin, size_t end) {
        size_t bad = 0, hit_count = 0;
        for (size_t i = begin; i < end; ++i) {
            Ray ray;
            const bool ok = make_ray(&rays.values[8 * i], ray);
            bad += !ok;
            if (args.any_hit) {
                occluded[i] = ok && accel->occluded(ray) ? 1 : 0;
                hit_count += occluded[i];
            } else {
                Hit h = ok ? accel->intersect(ray) : Hit{};
                if (!h.found()) h = Hit{};  // a miss reports t = +inf, not the ray's tmax
                hits[i] = h;
                hit_count += h.found();
            }
        }
        invalid += bad;
        found += hit_count;
        progress.advance(end - begin);
    });
    const double seconds = ms_since(start) / 1000.0;
    progress.finish();

    std::printf("trace   %s %s rays in %s, %s rays/s: %zu %s, %zu not\n", args.any_hit ? "any-hit" : "closest-hit",
                format_si(double(n)).c_str(), format_duration(seconds).c_str(),
                format_si(seconds > 0 ? double(n) / seconds : 0.0).c_str(), found.load(),
                args.any_hit ? "occluded" : "hit", n - found.load());
    if (invalid)
        std::printf("note    %zu rays were invalid (NaN, infinite origin or direction, zero direction or "
                    "tmin > tmax) and count as misses\n", invalid.load());
    if (args.any_hit)
        write_npy_u8(output, occluded);
    else
        write_npy_hits(output, hits);
    std::printf("wrote   %s\n", args.output.c_str());
    return 0;
}

}  // namespace

Command add_trace_command(CLI::App& app) {
    auto args = std::make_shared<TraceArgs>();
    CLI::App* cmd = app.add_subcommand("trace", "trace the rays of a .npy file through a structure built over SCENE");
    cmd->footer("Input: float32 (or float64) array of shape (N, 8), one ray per row: ox oy oz dx dy dz tmin tmax; "
                "hits are accepted for tmin <= t <= tmax, t in units of the direction's length. A row with a NaN, "
                "an infinite origin or direction component, a zero direction or tmin > tmax is answered as a "
                "miss.\nOutput: a structured array of shape (N,) with fields t (float32, +inf on a miss), prim "
                "(uint32, 4294967295 on a miss), u, v (float32 barycentrics of vertices 1 and 2); with --any-hit "
                "a uint8 array of shape (N,), 1 where something lies within [tmin, tmax].");
    add_scene_argument(cmd, args->scene);
    add_accel_options(cmd, args->accel);
    cmd->add_option("-r,--rays", args->rays, "rays to trace: .npy float array of shape (N, 8)")
        ->required()
        ->type_name("FILE");
    cmd->add_option("-o,--output", args->output, ".npy file to write the hits (or occlusion flags) to (- for stdout)")
        ->required()
        ->type_name("FILE");
    cmd->add_flag("-f,--force", args->force, kForceHelp);
    cmd->add_flag("--any-hit", args->any_hit, "only ask whether each ray is blocked (faster), write a uint8 array");
    add_threads_option(cmd, args->threads);
    return {cmd, [args] { return run_trace(*args); }};
}

}  // namespace thicket::cli
