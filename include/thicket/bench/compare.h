#pragma once
/// `thicket compare`: the lecture's comparison table of acceleration structures, measured. Per
/// structure: how it partitions (object or space), how its build time grows with N (a power-law
/// exponent fitted over scenes of growing size made from the scene, see scene_sizes.h), memory per
/// primitive, SAH cost, work per ray and Mrays/s on primary and diffuse rays (the bench's ray sets
/// and timing loop, runner.h).
#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/bench/bench_row.h"
#include "thicket/bench/growth_fit.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// Smallest size the growth exponent is fitted from by default: below it a build takes well under
/// a millisecond and fixed costs (allocation, the root's bounds) hide the growth.
inline constexpr size_t kDefaultFitMinSize = 10'000;
/// Largest default growth size.
inline constexpr size_t kDefaultMaxGrowthSize = 1'000'000;
/// Ray sets the comparison times.
inline constexpr const char* kCompareSets[] = {"primary", "diffuse"};

/// The default growth sizes: 10^3, 3*10^3, 10^4, ... (half decades) below `max_size`, then
/// `max_size` itself (10^3..10^6 in seven sizes by default). Throws Error for max_size < 1.
std::vector<size_t> default_growth_sizes(size_t max_size = kDefaultMaxGrowthSize);
/// Parses a comma-separated list of sizes, each an integer or a number in e notation (1e5),
/// at least 1 and at most kMaxSceneSize; sorted, duplicates dropped. Throws Error quoting a bad item.
std::vector<size_t> parse_size_list(std::string_view text);

/// The structures compared when none are named: every registered structure, by its bare name
/// (its default options), except those with Partitioning::None (brute force: O(N) per ray, it
/// would dominate the run; name it to include it, it is then timed on a sample of the rays).
std::vector<std::string> default_compare_specs();
/// How the registered structure of `spec` partitions (Unknown for an unknown name).
Partitioning spec_partitioning(std::string_view spec);

struct GrowthOptions {
    std::vector<size_t> sizes = default_growth_sizes();
    /// Builds per size: up to this many, stopping once they have taken repeat_budget_ms in all; the
    /// median is kept (small scenes build in microseconds, where one build is mostly noise).
    int max_builds = 5;
    double repeat_budget_ms = 1000.0;
    /// A structure's sweep stops before a size whose build is predicted to take longer than this
    /// (from the last build, growing at least linearly, or by the last two sizes' slope if steeper),
    /// so that a quadratic builder cannot hold the run for hours. 0: never stop.
    double build_budget_s = 60.0;
    double fit_min_size = double(kDefaultFitMinSize);  ///< the exponent is fitted over sizes >= this
    /// One build of `spec` over a scene, returning its cost in ms; empty: a real single-threaded
    /// build, timed. Tests give a counted cost here, so that the repeat, budget and fit rules are
    /// checked exactly rather than on a clock.
    std::function<double(const std::string& spec, const Scene& scene)> build;
};

struct GrowthPoint {
    size_t n = 0;
    double build_ms = 0.0;  ///< median of the builds
    int builds = 0;
};

struct Growth {
    std::vector<GrowthPoint> points;
    PowerFit fit;                    ///< build_ms against n over points with n >= fit_min_size
    std::optional<size_t> stopped_at;  ///< first size skipped because of build_budget_s
    double predicted_s = 0.0;          ///< its predicted build time
};

/// Builds `spec` over every scene in `sized` (increasing sizes, e.g. from scene_of_size()) on one
/// thread by the rules of `options`, then fits the exponent. `after_size` (may be empty) is called
/// after each size with the point just measured.
Growth measure_growth(const std::string& spec, std::span<const Scene> sized, const GrowthOptions& options,
                      const std::function<void(const GrowthPoint&)>& after_size = {});

/// One row of the comparison: one structure over one scene.
struct CompareRow {
    std::string scene;   ///< scene label
    size_t primitives = 0;
    size_t shapes = 0;   ///< of the primitives, shapes; the rest are triangles
    std::string accel;   ///< as asked for
    std::string spec;    ///< canonical
    Partitioning partitioning = Partitioning::Unknown;
    std::vector<BenchRow> speed;  ///< bench_scene() rows: kCompareSets x thread counts
    std::optional<Growth> growth; ///< none with --no-growth

    /// The speed row of `set` on `threads` threads, or null.
    const BenchRow* find(std::string_view set, unsigned threads) const;
    /// Build time, memory and SAH cost of the full scene (from the first speed row; 0 without rows).
    double build_ms() const;
    size_t structure_bytes() const;
    double structure_bytes_per_primitive() const;
    double sah_cost() const;
};

}  // namespace thicket
