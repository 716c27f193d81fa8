// `thicket closest` and `thicket occupancy`: point queries over the points of a .npy file.
#include <chrono>
#include <string>
#include <vector>
#include <cstdio>
#include <cstring>

#include "common.h"
#include "point_commands.h"
#include "thicket/instances/instances.h"
#include "thicket/query/point_queries.h"
#include "thicket/core/error.h"
#include "thicket/util/npy.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

namespace {

struct PointArgs {
    std::string scene;
    AccelChoice accel{kClosestPointSpec, ""};  // the fastest closest points (its 8-wide point traversal)
    std::string points;
    std::string output;
    unsigned threads = 0;
    bool force = false;
    bool signed_distance = false;
    int samples = 3;
};

/// The points of a .npy file (N, 3), every value finite (query/point_queries.h refuses the others).
/// float32 only: closest points and occupancy are computed in float32 by every structure (no
/// precision=double form answers them), so a float64 file is refused rather than rounded.
std::vector<Vec3> read_points(const std::string& path) {
    NpyFile file(path);
    if (file.holds_float64())
        throw Error(path + ": float64 points: closest points and occupancy are computed in float32 by every "
                           "structure (precision=double ones included); save the points as float32");
    const NpyFloatArray values = file.read_matrix(3);
    const size_t n = values.shape[0];
    std::vector<Vec3> points(n);
    for (size_t i = 0; i < n; ++i) points[i] = {values.values[3 * i], values.values[3 * i + 1], values.values[3 * i + 2]};
    const size_t bad = first_non_finite(points);
    if (bad < n) throw Error(path + ": point " + std::to_string(bad) + " is not finite");
    std::printf("points  %s: %zu points\n", path.c_str(), n);
    return points;
}

int run_closest(const PointArgs& args) {
    if (args.signed_distance) check_parity_samples(args.samples);
    const std::optional<AccelSpec> spec = validate_accel_choice(args.accel);
    // Checked before any work: an existing output needs --force, and an input is never an output.
    const std::string output = prepare_output(args.output, args.force, {args.scene, args.points, args.accel.load});
    const std::vector<Vec3> points = read_points(args.points);
    const size_t n = points.size();
    Scene scene = load_scene_verbose(args.scene);
    // Closest points have no two-level walk: a scene with instances (a glTF whose nodes share a
    // mesh) is answered over its flattened copy, whose ids are the ones a trace of it reports.
    if (!scene.instances.empty()) scene = flatten_instances(scene, scene.instances);
    const std::unique_ptr<Accel> accel = make_accel_verbose(args.accel, spec, scene, args.threads);
    const PointQueries queries(*accel, scene);
    if (&queries.closest_accel() != accel.get())
        std::printf("note    %s does not answer closest points itself: a bvh8 over the same scene answers them\n",
                    accel->spec().c_str());

    std::vector<NearestPoint> closest(n);
    std::vector<uint8_t> inside(args.signed_distance ? n : 0);
    Progress progress("closest", n, "points");
    BatchOptions batch;
    batch.threads = args.threads;
    batch.progress = [&](size_t done) { progress.advance(done); };
    const auto start = std::chrono::steady_clock::now();
    queries.closest_points(points, closest, batch);
    if (args.signed_distance) {  // the sign only: the distances are the closest points' own
        batch.progress = nullptr;
        queries.occupancy(points, inside, args.samples, batch);
    }
    const double seconds = ms_since(start) / 1000.0;
    progress.finish();
    std::printf("closest %zu points in %s\n", n, format_duration(seconds).c_str());

    // Records of 28 bytes: x y z distance (float32), prim (uint32), u v (float32).
    std::vector<unsigned char> records(28 * n);
    for (size_t i = 0; i < n; ++i) {
        const NearestPoint& s = closest[i];
        const float values[4] = {s.point.x, s.point.y, s.point.z, args.signed_distance && inside[i] ? -s.distance : s.distance};
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

int run_occupancy(const PointArgs& args) {
    check_parity_samples(args.samples);
    const std::optional<AccelSpec> spec = validate_accel_choice(args.accel);
    const std::string output = prepare_output(args.output, args.force, {args.scene, args.points, args.accel.load});
    const std::vector<Vec3> points = read_points(args.points);
    const Scene scene = load_scene_verbose(args.scene);
    const std::unique_ptr<Accel> accel = make_accel_verbose(args.accel, spec, scene, args.threads);
    std::vector<uint8_t> inside(points.size());
    Progress progress("occupancy", points.size(), "points");
    BatchOptions batch;
    batch.threads = args.threads;
    batch.progress = [&](size_t done) { progress.advance(done); };
    const auto start = std::chrono::steady_clock::now();
    PointQueries(*accel, scene).occupancy(points, inside, args.samples, batch);
    const double seconds = ms_since(start) / 1000.0;
    progress.finish();
    size_t count = 0;
    for (uint8_t v : inside) count += v;
    std::printf("inside  %zu of %zu points in %s\n", count, points.size(), format_duration(seconds).c_str());
    write_npy_u8(output, inside);
    std::printf("wrote   %s\n", args.output.c_str());
    return 0;
}

/// The arguments both commands share.
void add_point_arguments(CLI::App* cmd, PointArgs& args) {
    add_scene_argument(cmd, args.scene);
    add_accel_options(cmd, args.accel);
    cmd->add_option("-p,--points", args.points, "query points: .npy float32 array of shape (N, 3)")
        ->required()
        ->type_name("FILE");
    cmd->add_option("-o,--output", args.output, ".npy file to write the answers to")->required()->type_name("FILE");
    add_threads_option(cmd, args.threads);
    cmd->add_flag("-f,--force", args.force, kForceHelp);
}

const std::string kSamplesHelp = "directions whose crossing parities vote on inside (odd, 1 to " +
                                 std::to_string(kMaxParitySamples) + ")";

}  // namespace

Command add_closest_command(CLI::App& app) {
    auto args = std::make_shared<PointArgs>();
    CLI::App* cmd = app.add_subcommand("closest", "the closest surface point of every point of a .npy file");
    cmd->footer("Input: float32 array of shape (N, 3), one point per row; every value finite (float64 is refused: "
                "point queries are computed in float32 by every structure, precision=double ones included).\n"
                "Output: a structured array of shape (N,) with fields x, y, z (the closest point), distance "
                "(float32; with --signed negative inside the surface), prim (uint32, 4294967295 for an empty "
                "scene), u, v (float32 barycentrics of vertices 1 and 2). Triangle scenes only. brute, bvh and "
                "bvh8 (the default) answer closest points themselves; with another structure a bvh8 over the same "
                "scene answers them (and the structure asked for decides inside for --signed).");
    add_point_arguments(cmd, *args);
    cmd->add_flag("--signed", args->signed_distance,
                  "signed distance: negative where the point is inside (the parity vote of `thicket occupancy`)");
    cmd->add_option("--samples", args->samples, kSamplesHelp + ", with --signed")->default_val(3);
    return {cmd, [args] { return run_closest(*args); }};
}

Command add_occupancy_command(CLI::App& app) {
    auto args = std::make_shared<PointArgs>();
    args->accel = AccelChoice{kClosestPointSpec, ""};
    CLI::App* cmd = app.add_subcommand("occupancy", "whether each point of a .npy file lies inside the closed surface");
    cmd->footer("Input: float32 array of shape (N, 3), one point per row; every value finite (float64 is refused: "
                "point queries are computed in float32 by every structure, precision=double ones included).\n"
                "Output: a uint8 array of shape (N,), 1 inside and 0 outside: the parity of the surface crossings "
                "along --samples fixed directions (none along an axis or a diagonal), the majority deciding. "
                "Meaningful for closed (watertight) surfaces; any structure answers.");
    add_point_arguments(cmd, *args);
    cmd->add_option("--samples", args->samples, kSamplesHelp)->default_val(3);
    return {cmd, [args] { return run_occupancy(*args); }};
}

}  // namespace thicket::cli
