#pragma once
/// The bench's measuring loop for one scene: build every tracer, then for every ray set a counting
/// pass and timed passes on one thread and on all threads, each row checked against the reference
/// tracer's answers ray for ray. Every row's passes are paired with passes of the reference on the
/// same rays (reference, tracer, reference, tracer, ...), so that its speed ratio to the reference
/// is taken under the same machine conditions.
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "thicket/bench/bench_row.h"
#include "thicket/bench/ray_sets.h"
#include "thicket/bench/tracer.h"

namespace thicket {

/// Name of the tracer every other one is compared with, when it is present.
inline constexpr const char* kReferenceTracer = "embree-high";

struct BenchOptions {
    int reps = 5;             ///< timed passes per row (after one warm-up pass)
    unsigned threads = 0;     ///< "all threads": this many (0: one per core); rows for 1 and this
    /// A tracer whose estimated single-thread pass over a set takes longer than this is timed on
    /// every k-th ray of the set, k chosen to bring the pass down to about a tenth of this time
    /// (brute force on large scenes would take hours otherwise). The reference tracer never is.
    /// 0: never sample.
    double pass_budget_ms = 1000.0;
    /// A row whose timed passes got less than kDisturbedUtilization of the CPU time is timed again,
    /// up to this many attempts in all; the attempt with the best utilization is kept.
    int max_attempts = 3;
    /// The CPU utilization to judge attempt `attempt` (from 1) by, given the one measured; empty:
    /// the measured one. Tests give a scripted sequence here, so that the retry rule is checked
    /// without loading the machine.
    std::function<double(int attempt, double measured)> utilization;
};

/// Progress reporting and messages; every member may be left empty.
struct BenchCallbacks {
    std::function<void(uint64_t steps)> advance;  ///< called as steps (see bench_steps()) complete
};

/// Thread counts the rows are made for: {1, N}, or {1} when N resolves to 1.
std::vector<unsigned> bench_thread_counts(unsigned threads);
/// Steps one scene's run reports through BenchCallbacks::advance, for a progress bar's total.
uint64_t bench_steps(size_t tracers, size_t sets, const BenchOptions& options);

/// Measures every tracer (made one at a time, reference first and kept to the end) on every set
/// over `scene`, whose label goes into the rows. Rows come in tracer order (reference first), then
/// set order, then thread count. A row's ratio is the median over its paired passes of its Mrays/s
/// over the reference's. Without a reference tracer the rows have no agreement and no ratio.
std::vector<BenchRow> bench_scene(const Scene& scene, const std::string& label, std::span<const TracerFactory> tracers,
                                  std::span<const RaySet> sets, const BenchOptions& options,
                                  const BenchCallbacks& callbacks = {});

/// Merges the rows of `rounds` runs of bench_scene() with the same tracers and sets (rows in the
/// same order; throws Error otherwise) into one row each: Mrays/s, ratio, build time and
/// utilization are medians over the rounds, mrays_min / mrays_max the slowest and fastest round
/// median (the spread between runs, which on a shared machine is larger than within one), the
/// rest from the first round. A single round is returned as it is, with its pass-to-pass range.
std::vector<BenchRow> merge_bench_rounds(std::span<const std::vector<BenchRow>> rounds);

}  // namespace thicket
