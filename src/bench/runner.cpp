#include "thicket/bench/runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>

#include "thicket/bench/agreement.h"
#include "thicket/bench/arbiter.h"
#include "thicket/bench/primitive_probe.h"
#include "thicket/bench/timing.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket {

namespace {

// The reference's answers to every set, kept to check every later tracer against.
struct ReferenceAnswers {
    std::vector<std::vector<Hit>> hits;        // per set (closest-hit sets)
    std::vector<std::vector<uint8_t>> flags;   // per set (any-hit sets)
};

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void run_pass(const Tracer& tracer, const RaySet& set, std::span<const Ray> rays, std::vector<Hit>& hits,
              std::vector<uint8_t>& flags, unsigned threads) {
    if (set.any_hit) {
        flags.resize(rays.size());
        tracer.occluded(rays, flags, threads);
    } else {
        hits.resize(rays.size());
        // The set's rays in their order are coherent; a sample of every k-th is not.
        tracer.trace(rays, hits, threads, set.coherent && rays.data() == set.rays.data());
    }
}

// Every k-th ray, where k brings an estimated single-thread pass over the budget down to a tenth of
// it: structures just over the budget are rare, far over it (brute force) common. The estimate
// comes from evenly spaced probe rays, each probe traced twice and the second (warm) run timed;
// the probe grows until it takes long enough to time reliably.
size_t choose_stride(const Tracer& tracer, const RaySet& set, double budget_ms) {
    const size_t n = set.rays.size();
    if (n == 0 || budget_ms <= 0.0) return 1;
    std::vector<Hit> hits;
    std::vector<uint8_t> flags;
    size_t m = std::min<size_t>(n, 64);
    while (true) {
        std::vector<Ray> probe(m);
        for (size_t i = 0; i < m; ++i) probe[i] = set.rays[i * n / m];
        run_pass(tracer, set, probe, hits, flags, 1);
        const auto start = std::chrono::steady_clock::now();
        run_pass(tracer, set, probe, hits, flags, 1);
        const double ms = seconds_since(start) * 1e3;
        if (ms > 0.05 * budget_ms || m == n) {
            const double estimate = ms * double(n) / double(m);
            return estimate <= budget_ms ? 1 : size_t(std::ceil(estimate / (0.1 * budget_ms)));
        }
        m = std::min(n, m * 4);
    }
}

double hit_fraction(const RaySet& set, const std::vector<Hit>& hits, const std::vector<uint8_t>& flags) {
    const size_t n = set.any_hit ? flags.size() : hits.size();
    if (n == 0) return 0.0;
    size_t found = 0;
    if (set.any_hit)
        for (uint8_t f : flags) found += f != 0;
    else
        for (const Hit& h : hits) found += h.found();
    return double(found) / double(n);
}

// The rays one row traces: the whole set, or every stride-th ray with its index in the set.
struct RowRays {
    const RaySet& set;
    size_t stride = 1;
    std::vector<Ray> sample;
    std::vector<uint32_t> index;

    RowRays(const RaySet& s, size_t k) : set(s), stride(k) {
        if (stride == 1) return;
        for (size_t i = 0; i < set.rays.size(); i += stride) {
            sample.push_back(set.rays[i]);
            index.push_back(uint32_t(i));
        }
    }
    std::span<const Ray> rays() const { return stride > 1 ? std::span<const Ray>(sample) : set.rays; }
};

// What timing one row produced.
struct RowTiming {
    PassTimes times;              // the tracer's own passes
    std::optional<double> ratio;  // median over paired passes of its Mrays/s over the reference's
    double utilization = 1.0;
    int attempts = 0;
};

// Times `tracer` on `rays` with `threads` threads, paired pass for pass with `reference` on the
// whole set when one is given. An attempt whose passes got too little CPU time is repeated; the
// best one is kept. Leaves the tracer's answers in hits / flags.
RowTiming time_row(const Tracer& tracer, const Tracer* reference, const RaySet& set, std::span<const Ray> rays,
                   unsigned threads, const BenchOptions& options, std::vector<Hit>& hits, std::vector<uint8_t>& flags,
                   const std::function<void()>& advance) {
    // Threads a pass can keep busy: a small sample may not fill every thread's chunk.
    const size_t chunks = std::max<size_t>(1, (rays.size() + kTraceGrain - 1) / kTraceGrain);
    const double busy = double(std::min<size_t>(threads, chunks));
    auto pass = [&] { run_pass(tracer, set, rays, hits, flags, threads); };
    std::vector<Hit> ref_hits;
    std::vector<uint8_t> ref_flags;
    auto ref_pass = [&] { run_pass(*reference, set, set.rays, ref_hits, ref_flags, threads); };

    RowTiming best;
    for (int attempt = 1;; ++attempt) {
        // Only the first attempt advances the progress bar: its total counts one attempt.
        const std::function<void()> after = attempt == 1 ? advance : std::function<void()>();
        RowTiming t;
        if (reference) {
            const auto [ref, own] = time_interleaved(options.reps, ref_pass, pass, after);
            std::vector<double> ratios;
            for (size_t i = 0; i < own.seconds.size(); ++i) {
                const double ref_rate = mrays_per_second(set.rays.size(), ref.seconds[i]);
                if (ref_rate > 0.0) ratios.push_back(mrays_per_second(rays.size(), own.seconds[i]) / ref_rate);
            }
            if (!ratios.empty()) t.ratio = median(ratios);
            t.times = own;
        } else {
            t.times = time_passes(options.reps, pass, after);
        }
        t.utilization = t.times.cpu_utilization(busy);
        if (options.utilization) t.utilization = options.utilization(attempt, t.utilization);
        t.attempts = attempt;
        if (attempt == 1 || t.utilization > best.utilization) best = t;
        best.attempts = attempt;
        if (best.utilization >= kDisturbedUtilization || attempt >= options.max_attempts) return best;
    }
}

}  // namespace

std::vector<unsigned> bench_thread_counts(unsigned threads) {
    const unsigned all = resolve_threads(threads);
    return all > 1 ? std::vector<unsigned>{1, all} : std::vector<unsigned>{1};
}

uint64_t bench_steps(size_t tracers, size_t sets, const BenchOptions& options) {
    const uint64_t per_set = 1 + bench_thread_counts(options.threads).size() * uint64_t(options.reps + 1);
    return uint64_t(tracers) * (1 + uint64_t(sets) * per_set);
}

std::vector<BenchRow> bench_scene(const Scene& scene, const std::string& label, std::span<const TracerFactory> tracers,
                                  std::span<const RaySet> sets, const BenchOptions& options,
                                  const BenchCallbacks& callbacks) {
    if (options.reps < 1) throw Error("--reps must be at least 1");
    auto advance = [&](uint64_t steps) {
        if (callbacks.advance) callbacks.advance(steps);
    };
    const std::vector<unsigned> thread_counts = bench_thread_counts(options.threads);

    // The reference goes first, so that every later row can be checked against its answers.
    std::vector<const TracerFactory*> order;
    for (const TracerFactory& f : tracers)
        if (f.name == kReferenceTracer) order.push_back(&f);
    const bool have_reference = !order.empty();
    for (const TracerFactory& f : tracers)
        if (f.name != kReferenceTracer) order.push_back(&f);

    // A structure naming another primitive than the reference must really hit it there: probed
    // alone with either triangle test, the primitive gives exactly the reported t, u, v.
    const PrimitiveProbe moller(scene, "moller"), watertight(scene, "watertight");
    // A ray the rule still rejects is settled in double precision (bench/arbiter.h).
    const RoundingArbiter arbiter(scene);
    ReferenceAnswers reference;
    std::unique_ptr<Tracer> reference_tracer;  // kept to pair every later row's passes with
    std::vector<BenchRow> rows;
    for (const TracerFactory* factory : order) {
        const bool is_reference = factory->name == kReferenceTracer;
        std::unique_ptr<Tracer> tracer = factory->make();

        // Build on one thread and on all; a single-threaded builder is built once.
        std::vector<double> build_ms(thread_counts.size());
        if (tracer->parallel_build()) {
            for (size_t k = 0; k < thread_counts.size(); ++k) build_ms[k] = tracer->build(scene, thread_counts[k]);
        } else {
            std::fill(build_ms.begin(), build_ms.end(), tracer->build(scene, 1));
        }
        const TracerFigures fig = tracer->figures();
        advance(1);

        for (size_t s = 0; s < sets.size(); ++s) {
            const RaySet& set = sets[s];
            const RowRays rr(set, is_reference ? 1 : choose_stride(*tracer, set, options.pass_budget_ms));
            const std::span<const Ray> rays = rr.rays();
            RayCounters counters;
            const bool counted = tracer->count(rays, set.any_hit, counters, thread_counts.back());
            advance(1);

            for (size_t k = 0; k < thread_counts.size(); ++k) {
                std::vector<Hit> hits;
                std::vector<uint8_t> flags;
                const RowTiming timing = time_row(*tracer, reference_tracer.get(), set, rays, thread_counts[k],
                                                  options, hits, flags, [&] { advance(1); });

                BenchRow row;
                row.scene = label;
                row.primitives = scene.instances.empty() ? scene.primitive_count()
                                                         : size_t(scene.instanced_primitive_count());
                row.shapes = scene.shapes.size();
                row.accel = factory->name;
                row.spec = fig.spec;
                row.set = set.name;
                row.any_hit = set.any_hit;
                row.threads = thread_counts[k];
                row.set_rays = set.rays.size();
                row.rays = rays.size();
                row.stride = rr.stride;
                row.reps = options.reps;
                row.mrays = mrays_per_second(rays.size(), timing.times.median());
                row.mrays_min = mrays_per_second(rays.size(), timing.times.max());
                row.mrays_max = mrays_per_second(rays.size(), timing.times.min());
                row.ratio = is_reference && row.mrays > 0 ? std::optional<double>(1.0) : timing.ratio;
                row.cpu_util = timing.utilization;
                row.attempts = timing.attempts;
                row.build_ms = build_ms[k];
                row.build_parallel = tracer->parallel_build();
                row.bytes = fig.bytes;
                row.structure_bytes = fig.structure_bytes;
                row.primitive_bytes = fig.primitive_bytes;
                row.nodes = fig.nodes;
                row.sah_cost = fig.sah_cost;
                if (counted && !rays.empty()) {
                    row.nodes_per_ray = double(counters.nodes) / double(rays.size());
                    row.prims_per_ray = double(counters.prims) / double(rays.size());
                    uint64_t visits = 0;
                    for (uint64_t v : counters.entered) visits += v;
                    if (visits)
                        for (uint64_t v : counters.entered) row.entered_share.push_back(double(v) / double(visits));
                }
                row.hit_rate = hit_fraction(set, hits, flags);

                if (is_reference && k == 0) {
                    reference.hits.resize(sets.size());
                    reference.flags.resize(sets.size());
                    reference.hits[s] = hits;
                    reference.flags[s] = flags;
                }
                if (have_reference) {
                    const std::span<const Ray> traced = rr.rays();
                    const TieCheck tie_is_real = [&](size_t i, const Hit& h) {
                        return identical_hits(moller.hit(h.prim, traced[i]), h) ||
                               identical_hits(watertight.hit(h.prim, traced[i]), h);
                    };
                    const HitArbiter settle_hits = [&](size_t i, const Hit& r, const Hit& c) {
                        return arbiter.candidate_within_rounding(traced[i], r, c);
                    };
                    // Flags name no primitive: the candidate's any-hit answer is settled with
                    // both structures' closest hits within the ray's interval as witnesses
                    // (RoundingArbiter::occlusion_within_rounding), so that a wrong any-hit path
                    // shows even where its closest-hit path is right.
                    const FlagArbiter settle_flags = [&](size_t i) {
                        const std::span<const Ray> one(&traced[i], 1);
                        Hit r, c;
                        reference_tracer->trace(one, std::span<Hit>(&r, 1), 1, false);
                        tracer->trace(one, std::span<Hit>(&c, 1), 1, false);
                        return arbiter.occlusion_within_rounding(traced[i], flags[i] != 0, r, c);
                    };
                    const bool arbitrate = !is_reference && reference_tracer;
                    const Agreement a =
                        set.any_hit ? compare_occlusion(reference.flags[s], flags, rr.index,
                                                        arbitrate ? settle_flags : FlagArbiter())
                                    : compare_hits(reference.hits[s], hits, rr.index,
                                                   tracer->hits_from_thicket_tests() ? tie_is_real : TieCheck(),
                                                   arbitrate ? settle_hits : HitArbiter());
                    row.agree = a.percent();
                    row.disagreeing = a.disagreeing();
                    row.arbitrated = a.arbitrated;
                    if (!set.any_hit) {
                        row.max_dt = a.max_dt;
                        row.max_dt_rel = a.max_dt_rel;
                    }
                }
                rows.push_back(std::move(row));
            }
        }
        if (is_reference) reference_tracer = std::move(tracer);
    }
    return rows;
}

std::vector<BenchRow> merge_bench_rounds(std::span<const std::vector<BenchRow>> rounds) {
    if (rounds.empty()) return {};
    // One round keeps its pass-to-pass range: "merging" it would collapse the range to its median.
    if (rounds.size() == 1) return rounds.front();
    std::vector<BenchRow> merged = rounds.front();
    for (size_t i = 0; i < merged.size(); ++i) {
        BenchRow& m = merged[i];
        std::vector<double> mrays, ratio, build, util;
        int attempts = 0;
        for (const std::vector<BenchRow>& round : rounds) {
            if (round.size() != merged.size() || round[i].accel != m.accel || round[i].set != m.set ||
                round[i].threads != m.threads || round[i].scene != m.scene)
                throw Error("merge_bench_rounds: the rounds did not measure the same rows");
            mrays.push_back(round[i].mrays);
            build.push_back(round[i].build_ms);
            util.push_back(round[i].cpu_util);
            if (round[i].ratio) ratio.push_back(*round[i].ratio);
            attempts = std::max(attempts, round[i].attempts);
        }
        m.rounds = int(rounds.size());
        m.mrays = median(mrays);
        m.mrays_min = *std::min_element(mrays.begin(), mrays.end());
        m.mrays_max = *std::max_element(mrays.begin(), mrays.end());
        m.build_ms = median(build);
        m.cpu_util = median(util);
        m.attempts = attempts;
        if (!ratio.empty()) m.ratio = median(ratio);
    }
    return merged;
}

}  // namespace thicket
