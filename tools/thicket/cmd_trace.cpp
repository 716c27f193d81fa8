// `thicket trace`: closest-hit or any-hit queries for a batch of rays from a .npy file.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

#include "common.h"
#include "thicket/query/double_rays.h"
#include "thicket/query/ray_rows.h"
#include "thicket/core/error.h"
#include "thicket/util/input_file.h"
#include "thicket/util/npy.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

namespace {

struct TraceArgs {
    std::string scene;
    AccelChoice accel;
    std::string rays;
    std::string output;
    bool any_hit = false;
    bool count = false;
    bool all = false;
    bool coherent = false;
    bool reorder = false;
    bool force = false;
    unsigned threads = 0;
};

/// --all's packed records of `lists` (HitLists or HitListsD) over `rays` rays: ray '<u4', t,
/// prim '<u4', u, v, with t, u and v as wide as the hits hold them (4 bytes, or 8 for doubles).
template <class Lists>
std::vector<unsigned char> crossing_records(const Lists& lists, size_t rays) {
    constexpr size_t R = sizeof(std::remove_cvref_t<decltype(lists.hits[0].t)>), size = 8 + 3 * R;
    std::vector<unsigned char> records(lists.hits.size() * size);
    for (size_t row = 0; row < rays; ++row)
        for (size_t j = lists.splits[row]; j < lists.splits[row + 1]; ++j) {
            const auto& h = lists.hits[j];
            const uint32_t ray = uint32_t(row);
            unsigned char* r = records.data() + size * j;
            std::memcpy(r, &ray, 4);
            std::memcpy(r + 4, &h.t, R);
            std::memcpy(r + 4 + R, &h.prim, 4);
            std::memcpy(r + 8 + R, &h.u, R);
            std::memcpy(r + 8 + 2 * R, &h.v, R);
        }
    return records;
}

/// The rays of a trace: float32 rows (RayRows, traced in chunks) or a converted float64 batch
/// (RayBatchD, for precision=double structures). The batch queries (query/ray_rows.h,
/// query/double_rays.h) take either, so one path below writes both; only the widths differ.
template <class Rays>
constexpr bool kDouble = std::is_same_v<Rays, RayBatchD>;

size_t ray_count(const RayRows& rows) { return rows.count; }
size_t ray_count(const RayBatchD& batch) { return batch.size(); }

/// " in double" after a float64 batch's figures.
template <class Rays>
constexpr const char* kPrecisionNote = kDouble<Rays> ? ", in double" : "";

/// --count and --all: every surface crossing of each row's ray (Accel::all_hits, all_hits_double),
/// rows without a ray counted as 0 crossings. --all writes records (ray, t, prim, u, v), by ray
/// then t, with t, u and v as wide as the rays.
template <class Rays>
void write_crossings(const std::string& output, bool list_all, const Accel& accel, const Rays& rays,
                     const BatchOptions& batch) {
    const size_t n = ray_count(rays);
    const auto start = std::chrono::steady_clock::now();
    // The lists' size is known only once traced: count first (4 bytes a ray), and check what the
    // lists will take before listing them.
    std::vector<uint32_t> counts(n);
    crossing_counts(accel, rays, counts, batch);
    uint64_t total = 0;
    for (uint32_t c : counts) total += c;
    if (!list_all) {
        std::printf("count   %s crossings of %zu rays in %s%s\n", std::to_string(total).c_str(), n,
                    format_duration(ms_since(start) / 1000).c_str(), kPrecisionNote<Rays>);
        write_npy_u32(output, counts);
        return;
    }
    // float: each crossing is held by its chunk, then in the merged list (a chunk's vector may
    // hold twice its size while it grows), then as a 20-byte record; double: as HitD while
    // listed, then as a 32-byte record.
    check_memory(total * (kDouble<Rays> ? sizeof(HitD) + 32 : 3 * sizeof(Hit) + 20),
                 "--all: " + std::to_string(total) + " crossings of " + std::to_string(n) + " rays");
    const auto lists = [&] {
        if constexpr (kDouble<Rays>)
            return crossing_lists(accel, rays, counts, batch);
        else
            return crossing_lists(accel, rays, batch);
    }();
    const std::vector<unsigned char> records = crossing_records(lists, n);
    std::printf("all     %zu crossings of %zu rays in %s%s\n", lists.hits.size(), n,
                format_duration(ms_since(start) / 1000).c_str(), kPrecisionNote<Rays>);
    const char* wide = kDouble<Rays> ? "<f8" : "<f4";
    write_npy_records(output, {{"ray", "<u4"}, {"t", wide}, {"prim", "<u4"}, {"u", wide}, {"v", wide}},
                      lists.hits.size(), records);
}

void write_hits(const std::string& output, std::span<const Hit> hits) { write_npy_hits(output, hits); }

/// float64 hits as records t '<f8', prim '<u4', u '<f8', v '<f8' (t +inf on a miss).
void write_hits(const std::string& output, std::span<const HitD> hits) {
    std::vector<unsigned char> records(hits.size() * 28);
    for (size_t i = 0; i < hits.size(); ++i) {
        unsigned char* r = records.data() + 28 * i;
        const double t = hits[i].found() ? hits[i].t : std::numeric_limits<double>::infinity();
        std::memcpy(r, &t, 8);
        std::memcpy(r + 8, &hits[i].prim, 4);
        std::memcpy(r + 12, &hits[i].u, 8);
        std::memcpy(r + 20, &hits[i].v, 8);
    }
    write_npy_records(output, {{"t", "<f8"}, {"prim", "<u4"}, {"u", "<f8"}, {"v", "<f8"}}, hits.size(), records);
}

/// Traces `rays` as `args` asks (closest hit, any hit, --count or --all) and writes the answers.
/// Rows without a meaning are answered as misses (as the Python module does).
template <class Rays>
int trace_rays(const TraceArgs& args, const std::string& output, const Accel& accel, const Rays& rays) {
    const size_t n = ray_count(rays);
    BatchOptions batch;
    batch.threads = args.threads;
    if (args.count || args.all) {
        if (n > UINT32_MAX) throw Error(args.rays + ": more than 2^32 - 1 rays for --count or --all");
        write_crossings(output, args.all, accel, rays, batch);
        std::printf("wrote   %s\n", args.output.c_str());
        return 0;
    }
    using HitT = std::conditional_t<kDouble<Rays>, HitD, Hit>;
    std::vector<HitT> hits(args.any_hit ? 0 : n);
    std::vector<uint8_t> occluded(args.any_hit ? n : 0);
    Progress progress("trace", n, "rays");
    batch.coherent = args.coherent;
    batch.reorder = args.reorder;
    // Float rows go through for_each_ray_chunk, which reorders; float64 rows are traced as given.
    const bool reordered = !kDouble<Rays> && batch.reorder && !batch.coherent && n >= kReorderMin;
    batch.progress = [&](size_t done) { progress.advance(done); };
    const auto start = std::chrono::steady_clock::now();
    const size_t invalid =
        args.any_hit ? occlusions(accel, rays, occluded, batch) : closest_hits(accel, rays, std::span(hits), batch);
    const double seconds = ms_since(start) / 1000.0;
    progress.finish();
    size_t found = 0;
    if (args.any_hit)
        for (uint8_t o : occluded) found += o;
    else
        for (const HitT& h : hits) found += h.found();

    std::printf("trace   %s %s rays in %s, %s rays/s%s%s: %zu %s, %zu not\n",
                args.any_hit ? "any-hit" : "closest-hit", format_si(double(n)).c_str(),
                format_duration(seconds).c_str(), format_si(seconds > 0 ? double(n) / seconds : 0.0).c_str(),
                kPrecisionNote<Rays>, reordered ? " (reordered where costly, sort included)" : "", found,
                args.any_hit ? "occluded" : "hit", n - found);
    if (invalid)
        std::printf("note    %zu rays were invalid (NaN, infinite origin or direction, zero direction or "
                    "tmin > tmax) and count as misses\n", invalid);
    if (args.any_hit)
        write_npy_u8(output, occluded);
    else
        write_hits(output, hits);
    std::printf("wrote   %s\n", args.output.c_str());
    return 0;
}

int run_trace(const TraceArgs& args) {
    if (args.any_hit + args.count + args.all > 1) throw Error("trace: choose one of --any-hit, --count and --all");
    // The packet path is closest-hit's: refused where it would be ignored (the CLI's rule, common.h).
    if (args.coherent && (args.any_hit || args.count || args.all))
        throw Error(std::string("--coherent does not apply here: only closest-hit rays are traced in packets, and ") +
                    (args.any_hit ? "--any-hit" : args.count ? "--count" : "--all") + " asks another query");
    const std::optional<AccelSpec> spec = validate_accel_choice(args.accel);
    const std::string output = prepare_output(args.output, args.force, {args.scene, args.rays, args.accel.load});
    NpyFile ray_file(args.rays);  // its header read once, here; the data below
    if (ray_file.holds_float64()) {
        if (!spec || !takes_double_rays(*spec))
            throw Error(float64_rays_refusal(
                args.rays, spec ? "'" + args.accel.spec + "'" : std::string("a saved structure (--load)"),
                "save the rays as float32"));
        if (args.coherent)
            throw Error("--coherent does not apply here: " + args.rays +
                        " holds float64 rays, which no structure traces in packets");
        const std::vector<double> values = ray_file.read_matrix_double(8);
        const RayBatchD rays = make_rays(RayRowsD{values.data(), values.size() / 8, 8}, args.threads);
        std::printf("rays    %s: %zu float64 rays, traced in double\n", args.rays.c_str(), rays.size());
        const Scene scene = load_scene_verbose(args.scene);
        return trace_rays(args, output, *make_accel_verbose(args.accel, spec, scene, args.threads), rays);
    }
    const NpyFloatArray rays = ray_file.read_matrix(8);
    std::printf("rays    %s: %zu rays\n", args.rays.c_str(), rays.shape[0]);
    const Scene scene = load_scene_verbose(args.scene);
    return trace_rays(args, output, *make_accel_verbose(args.accel, spec, scene, args.threads),
                      RayRows{rays.values.data(), rays.shape[0], 8});
}

}  // namespace

Command add_trace_command(CLI::App& app) {
    auto args = std::make_shared<TraceArgs>();
    CLI::App* cmd = app.add_subcommand("trace", "trace the rays of a .npy file through a structure built over SCENE");
    cmd->footer("Input: float32 (or float64) array of shape (N, 8), one ray per row: ox oy oz dx dy dz tmin tmax; "
                "float64 rays only through a structure built with precision=double (brute, bvh), which traces "
                "them in double and writes t, u and v as float64 (every other structure refuses them: rounding "
                "would lose their precision); hits are accepted for tmin <= t <= tmax, t in units of the "
                "direction's length. A row with a NaN, an infinite origin or direction component, a zero "
                "direction or tmin > tmax is answered as a miss.\nOutput: a structured array of shape (N,) with "
                "fields t (float32, +inf on a miss), prim (uint32, 4294967295 on a miss), u, v (float32 "
                "barycentrics of vertices 1 and 2); with --any-hit a uint8 array of shape (N,), 1 where something "
                "lies within [tmin, tmax]. With --count a uint32 array of shape (N,): the number of surface "
                "crossings within [tmin, tmax] (a crossing through an edge or vertex that several triangles share "
                "counts once). With --all a structured array of shape (M,), one record per crossing, by ray then "
                "t: ray (uint32 row), t (float32), prim (uint32), u, v (float32). For float64 rays t, u and v "
                "are float64 in every output.");
    add_scene_argument(cmd, args->scene);
    add_accel_options(cmd, args->accel);
    cmd->add_option("-r,--rays", args->rays, "rays to trace: .npy float32 array of shape (N, 8) (float64 for precision=double)")
        ->required()
        ->type_name("FILE");
    cmd->add_option("-o,--output", args->output, ".npy file to write the hits (or occlusion flags) to (- for stdout)")
        ->required()
        ->type_name("FILE");
    cmd->add_flag("-f,--force", args->force, kForceHelp);
    cmd->add_flag("--any-hit", args->any_hit, "only ask whether each ray is blocked (faster), write a uint8 array");
    cmd->add_flag("--count", args->count, "count every surface crossing of each ray, write a uint32 array");
    cmd->add_flag("--all", args->all, "list every surface crossing of each ray, write (ray, t, prim, u, v) records "
                                      "(counted first: refused when the list would not fit in memory)");
    cmd->add_flag("--coherent", args->coherent,
                  "a hint that consecutive rays are neighbours (a camera's pixels in 4x4 tiles, or along a row): "
                  "structures with a packet path (bvh8) then trace 16 at a time; the answers are the same. Closest "
                  "hits of float32 rays only: refused with --any-hit, --count, --all and float64 rays");
    cmd->add_flag("--reorder", args->reorder,
                  "trace a batch of 4096 float32 rays or more (not --coherent) in blocks of up to 65536, each block "
                  "whose rays cost 200 ns or more sorted by direction octant and origin, each answer written to its "
                  "own row: the same answers, 1.05-1.13x faster on costly incoherent rays of interior scenes, slower "
                  "on rays that start on a surface in image order (the dragon's diffuse rays: 0.85x)");
    add_threads_option(cmd, args->threads);
    return {cmd, [args] { return run_trace(*args); }};
}

}  // namespace thicket::cli
