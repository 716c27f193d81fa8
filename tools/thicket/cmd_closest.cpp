// `thicket closest`: the closest surface point of each point of a .npy file.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "common.h"
#include "thicket/core/error.h"
#include "thicket/util/npy.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

namespace {

struct ClosestArgs {
    std::string scene;
    AccelChoice accel{"bvh8", ""};  // the fastest closest points (its 8-wide point traversal)
    std::string points;
    std::string output;
    unsigned threads = 0;
    bool force = false;
};

int run_closest(const ClosestArgs& args) {
    const std::optional<AccelSpec> spec = validate_accel_choice(args.accel);
    // Checked before any work: an existing output needs --force, and an input is never an output.
    const std::string output = prepare_output(args.output, args.force, {args.scene, args.points, args.accel.load});
    const NpyFloatArray points = read_npy_matrix(args.points, 3);
    const size_t n = points.shape[0];
    for (size_t i = 0; i < 3 * n; ++i)
        if (!std::isfinite(points.values[i]))
            throw Error(args.points + ": point " + std::to_string(i / 3) + " is not finite");
    std::printf("points  %s: %zu points\n", args.points.c_str(), n);
    const Scene scene = load_scene_verbose(args.scene);
    const std::unique_ptr<Accel> accel = make_accel_verbose(args.accel, spec, scene, args.threads);
    if (!accel->has_closest_point()) accel->closest_point({0, 0, 0});  // throws the reason

    std::vector<Vec3> query(n);
    for (size_t i = 0; i < n; ++i) query[i] = {points.values[3 * i], points.values[3 * i + 1], points.values[3 * i + 2]};
    std::vector<NearestPoint> closest(n);
    Progress progress("closest", n, "points");
    BatchOptions batch;
    batch.threads = args.threads;
    batch.progress = [&](size_t done) { progress.advance(done); };
    const auto start = std::chrono::steady_clock::now();
    accel->closest_points(query, closest, batch);
    const double seconds = ms_since(start) / 1000.0;
    progress.finish();
    std::printf("closest %zu points in %s\n", n, format_duration(seconds).c_str());

    // Records of 28 bytes: x y z distance (float32), prim (uint32), u v (float32).
    std::vector<unsigned char> records(28 * n);
    for (size_t i = 0; i < n; ++i) {
        const NearestPoint& s = closest[i];
        const float values[4] = {s.point.x, s.point.y, s.point.z, s.distance};
        unsigned char* r = records.data() + 28 * i;
        std::memcpy(r, values, 16);
        std::memcpy(r + 16, &s.prim, 4);
        std::memcpy(r + 20, &s.u, 4);
        std::memcpy(r + 24, &s.v, 4);
    }
    write_npy_records(output,
                      {{"x", "<f4"}, {"y", "<f4"}, {"z", "<f4"}, {"distance", "<f4"}, {"prim", "<u4"}, {"u", "<f4"},
                       {"v", "<f4"}},
                      n, records);
    std::printf("wrote   %s\n", args.output.c_str());
    return 0;
}

}  // namespace

Command add_closest_command(CLI::App& app) {
    auto args = std::make_shared<ClosestArgs>();
    CLI::App* cmd = app.add_subcommand("closest", "the closest surface point of every point of a .npy file");
    cmd->footer("Input: float32 (or float64) array of shape (N, 3), one point per row; every value finite.\n"
                "Output: a structured array of shape (N,) with fields x, y, z (the closest point), distance "
                "(float32), prim (uint32, 4294967295 for an empty scene), u, v (float32 barycentrics of vertices 1 "
                "and 2). Triangle scenes only; structures: brute, bvh and bvh8 (the default).");
    add_scene_argument(cmd, args->scene);
    add_accel_options(cmd, args->accel);
    cmd->add_option("-p,--points", args->points, "query points: .npy float array of shape (N, 3)")
        ->required()
        ->type_name("FILE");
    cmd->add_option("-o,--output", args->output, ".npy file to write the closest points to")
        ->required()
        ->type_name("FILE");
    add_threads_option(cmd, args->threads);
    cmd->add_flag("-f,--force", args->force, kForceHelp);
    return {cmd, [args] { return run_closest(*args); }};
}

}  // namespace thicket::cli
