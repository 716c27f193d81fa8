#pragma once
/// One row of the bench's results: one structure, one scene, one ray set, one thread count.
#include <cstddef>
#include <optional>
#include <vector>
#include <string>

namespace thicket {

/// Below this share of the CPU time its threads could use, a row's timed passes count as disturbed
/// by other work on the machine.
inline constexpr double kDisturbedUtilization = 0.9;

struct BenchRow {
    std::string scene;      ///< scene label (file name)
    size_t primitives = 0;
    size_t shapes = 0;      ///< of the primitives, shapes; the rest are triangles
    std::string accel;      ///< as asked for (a spec, or "embree-medium" / "embree-high")
    std::string spec;       ///< canonical spec, or the backend's description
    std::string set;        ///< ray set name
    bool any_hit = false;
    unsigned threads = 1;

    size_t set_rays = 0;    ///< rays in the set
    size_t rays = 0;        ///< rays traced per pass: set_rays, or a sample of them (stride > 1)
    size_t stride = 1;      ///< every stride-th ray of the set was traced (slow structures only)
    int reps = 0;           ///< timed passes (per round)
    int rounds = 1;         ///< times the whole measurement was repeated (merge_bench_rounds())
    double mrays = 0.0;     ///< median of the timed passes (with rounds > 1: median of round medians)
    double mrays_min = 0.0; ///< slowest timed pass (with rounds > 1: slowest round median)
    double mrays_max = 0.0; ///< fastest timed pass (with rounds > 1: fastest round median)
    std::optional<double> ratio;  ///< Mrays/s over Embree-high's on the same set and threads: the
                                  ///< median over passes timed in pairs with Embree-high's
    double cpu_util = 1.0;  ///< process CPU time / (wall time x threads kept busy) of the kept attempt
    int attempts = 1;       ///< timing attempts made (more than one when the first was disturbed)

    double build_ms = 0.0;  ///< build time with this row's thread count
    bool build_parallel = false;  ///< false: a single-threaded build, the same for every thread count
    size_t bytes = 0;       ///< all memory the structure holds
    size_t structure_bytes = 0, primitive_bytes = 0;
    size_t nodes = 0;
    double sah_cost = 0.0;  ///< 0: unknown

    std::optional<double> nodes_per_ray, prims_per_ray;  ///< from the counting pass, when supported
    /// Shares of interior node visits that entered 0, 1, 2, 3, 4, 5+ children (bvh8's counting
    /// pass; empty for the others).
    std::vector<double> entered_share;
    double hit_rate = 0.0;  ///< fraction of rays that hit (closest) or are occluded (any-hit)

    std::optional<double> agree;       ///< percent of rays agreeing with Embree-high
    size_t disagreeing = 0;
    size_t arbitrated = 0;  ///< rays counted as agreeing only because RoundingArbiter accepted them
    std::optional<double> max_dt, max_dt_rel;  ///< largest t difference to Embree-high where they agree

    double bytes_per_primitive() const { return primitives ? double(bytes) / double(primitives) : 0.0; }
};

}  // namespace thicket
