// The animated sequence of `thicket bench --animate`: per frame, each tracer's refit against a
// rebuild of the same frame, on the same rays from a camera that stays put.
#include "thicket/bench/animate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "thicket/bench/agreement.h"
#include "thicket/bench/timing.h"
#include "thicket/core/error.h"

namespace thicket {

AnimateMotion parse_animate_motion(std::string_view text) {
    if (text == "bend") return AnimateMotion::Bend;
    if (text == "explode") return AnimateMotion::Explode;
    throw Error("--motion '" + std::string(text) + "': expected bend or explode");
}

const char* animate_motion_name(AnimateMotion motion) {
    return motion == AnimateMotion::Bend ? "bend" : "explode";
}

namespace {

/// A value in [-1, 1] from a vertex index and an axis: splitmix64, so the jitter is the same on
/// every machine and independent of the order vertices are moved in.
float hashed_unit(uint64_t index, uint64_t axis) {
    uint64_t z = index * 3 + axis + 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return float(double(z >> 11) * 0x1.0p-53 * 2.0 - 1.0);
}

}  // namespace

std::vector<Vec3> animated_positions(std::span<const Vec3> rest, const Aabb& bounds, AnimateMotion motion,
                                     double phase) {
    std::vector<Vec3> out(rest.size());
    if (bounds.empty()) return out;
    const Vec3 c = bounds.center();
    const float size = std::max(max_component(bounds.extent()), 1e-30f);
    const float half_x = std::max(bounds.extent().x * 0.5f, 1e-30f);
    const auto s = float(phase);
    for (size_t i = 0; i < rest.size(); ++i) {
        const Vec3 p = rest[i] - c;
        if (motion == AnimateMotion::Bend) {
            const float along = p.x / half_x;  // -1 .. 1 over the scene
            const float angle = s * 0.785398f * along;
            out[i] = c + Vec3(p.x * std::cos(angle) - p.z * std::sin(angle), p.y - s * 0.15f * size * along * along,
                              p.x * std::sin(angle) + p.z * std::cos(angle));
        } else {
            const Vec3 jitter(hashed_unit(i, 0), hashed_unit(i, 1), hashed_unit(i, 2));
            out[i] = c + p * (1.0f + s) + jitter * (0.05f * size * s);
        }
    }
    return out;
}

Scene animated_frame(const Scene& rest, AnimateMotion motion, int frame, int frames) {
    Scene s = rest;
    const Aabb bounds = rest.bounds();
    const double phase = frames > 0 ? double(frame) / frames : 0.0;
    for (uint32_t id = 0; id < rest.geometry_count(); ++id) {
        const Geometry g = rest.geometry(id);
        if (g.vertex_count == 0) continue;
        const std::span<const Vec3> v(rest.mesh.positions.data() + g.vertex_first, g.vertex_count);
        s.set_vertices(id, animated_positions(v, bounds, motion, phase));
    }
    return s;
}

namespace {

/// Traces every set with both tracers, passes interleaved so drifts of a shared machine hit both;
/// returns the two rates (Mrays/s) and the refitted tracer's agreement with the rebuilt one.
struct TraceFigures {
    double mrays_a = 0.0, mrays_b = 0.0, agree = 100.0;
    size_t rays = 0;
};
TraceFigures trace_both(const Tracer& a, const Tracer& b, std::span<const RaySet> sets, const AnimateOptions& o) {
    TraceFigures f;
    double seconds_a = 0.0, seconds_b = 0.0;
    size_t agreeing = 0;
    for (const RaySet& set : sets) {
        const size_t n = set.rays.size();
        if (n == 0) continue;
        std::vector<Hit> hits_a(n), hits_b(n);
        std::vector<uint8_t> occ_a(n), occ_b(n);
        auto pass = [&](const Tracer& t, std::vector<Hit>& hits, std::vector<uint8_t>& occ) {
            if (set.any_hit)
                t.occluded(set.rays, occ, o.threads);
            else
                t.trace(set.rays, hits, o.threads, set.coherent);
        };
        const auto [ta, tb] = time_interleaved(
            o.reps, [&] { pass(a, hits_a, occ_a); }, [&] { pass(b, hits_b, occ_b); });
        seconds_a += ta.median();
        seconds_b += tb.median();
        f.rays += n;
        agreeing += set.any_hit ? compare_occlusion(occ_b, occ_a).agreeing : compare_hits(hits_b, hits_a).agreeing;
    }
    f.mrays_a = mrays_per_second(f.rays, seconds_a);
    f.mrays_b = mrays_per_second(f.rays, seconds_b);
    f.agree = f.rays ? 100.0 * double(agreeing) / double(f.rays) : 100.0;
    return f;
}

/// Median of `reps` calls of f() (each returning milliseconds), after one untimed call.
template <class F>
double median_ms(int reps, F&& f) {
    f();
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) ms.push_back(f());
    return median(ms);
}

/// Refuses a tracer that cannot refit, on a one-triangle scene, before the slow work.
void check_refits(const TracerFactory& factory, unsigned threads) {
    Scene tiny;
    tiny.name = "one triangle";
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    tiny.add_mesh(m);
    const std::unique_ptr<Tracer> t = factory.make();
    t->build(tiny, threads);
    try {
        t->refit(tiny, threads);
    } catch (const Error& e) {
        throw Error("--animate: " + std::string(e.what()) + " (refit: bvh, bvh8, obb and embree-refit)");
    }
}

}  // namespace

std::vector<AnimateRow> animate_scene(const Scene& rest, std::span<const TracerFactory> tracers,
                                      const AnimateOptions& options,
                                      const std::function<void(const AnimateRow&)>& on_row) {
    if (options.frames < 1 || options.frames > 1000)
        throw Error("--animate " + std::to_string(options.frames) + ": frames must be between 1 and 1000");
    if (options.reps < 1) throw Error("--reps must be at least 1");
    for (const TracerFactory& t : tracers) check_refits(t, options.threads);
    // The camera of the rest pose for every frame, as a renderer's would stay.
    const std::unique_ptr<Accel> rest_hits = build_accel(kRaySetHitSpec, rest, options.threads);
    const RaySetView view = ray_set_view(rest, *rest_hits, options.rays);

    std::vector<std::unique_ptr<Tracer>> kept;
    for (const TracerFactory& t : tracers) {
        kept.push_back(t.make());
        kept.back()->build(rest, options.threads);
    }
    std::vector<AnimateRow> rows;
    for (int frame = 1; frame <= options.frames; ++frame) {
        const Scene scene = animated_frame(rest, options.motion, frame, options.frames);
        const std::unique_ptr<Accel> hits_from = build_accel(kRaySetHitSpec, scene, options.threads);
        const std::vector<RaySet> sets = generate_ray_sets(scene, *hits_from, view, options.sets, options.rays,
                                                           options.threads);
        for (size_t k = 0; k < tracers.size(); ++k) {
            AnimateRow row;
            row.frame = frame;
            row.tracer = tracers[k].name;
            Tracer& a = *kept[k];
            try {
                row.refit_ms = median_ms(options.reps, [&] { return a.refit(scene, options.threads); });
            } catch (const Error& e) {
                // A refit the structure cannot make (bvh8: a triangle crossed the degenerate
                // test): rebuilt here, and refitted from this frame on.
                row.refused = e.what();
                a.build(scene, options.threads);
            }
            const std::unique_ptr<Tracer> b = tracers[k].make();
            row.rebuild_ms = median_ms(options.reps, [&] { return b->build(scene, options.threads); });
            row.sah_refit = a.figures().sah_cost;
            row.sah_rebuild = b->figures().sah_cost;
            const TraceFigures f = trace_both(a, *b, sets, options);
            row.mrays_refit = f.mrays_a;
            row.mrays_rebuild = f.mrays_b;
            row.agree = f.agree;
            row.rays = f.rays;
            rows.push_back(row);
            if (on_row) on_row(row);
        }
    }
    return rows;
}

namespace {

std::string fixed(double v, int decimals) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, v);
    return text;
}

}  // namespace

std::string animate_header() {
    char line[256];
    std::snprintf(line, sizeof line, "%5s  %-14s %10s %10s %8s %9s %9s %7s %8s %8s %7s %7s", "frame", "tracer",
                  "refit ms", "build ms", "speedup", "SAH refit", "SAH build", "SAH x", "Mr/s ref", "Mr/s bld",
                  "Mr/s x", "agree%");
    return line;
}

std::string format_animate_row(const AnimateRow& r) {
    const bool sah = r.sah_refit > 0.0 && r.sah_rebuild > 0.0;
    char line[512];
    std::snprintf(line, sizeof line, "%5d  %-14s %10s %10.3f %8s %9s %9s %7s %8.1f %8.1f %7.3f %7s", r.frame,
                  r.tracer.c_str(), r.refused.empty() ? fixed(r.refit_ms, 3).c_str() : "refused", r.rebuild_ms,
                  r.refused.empty() && r.refit_ms > 0 ? (fixed(r.rebuild_ms / r.refit_ms, 1) + "x").c_str() : "-",
                  sah ? fixed(r.sah_refit, 2).c_str() : "-", sah ? fixed(r.sah_rebuild, 2).c_str() : "-",
                  sah ? fixed(r.sah_refit / r.sah_rebuild, 3).c_str() : "-", r.mrays_refit, r.mrays_rebuild,
                  r.mrays_rebuild > 0 ? r.mrays_refit / r.mrays_rebuild : 0.0, fixed(r.agree, 2).c_str());
    std::string out = line;
    if (!r.refused.empty()) out += "\n       refit refused, rebuilt instead: " + r.refused;
    return out;
}

std::string format_animate_summary(std::span<const AnimateRow> rows) {
    std::map<std::string, std::vector<const AnimateRow*>> by_tracer;
    std::vector<std::string> order;
    for (const AnimateRow& r : rows) {
        if (!by_tracer.count(r.tracer)) order.push_back(r.tracer);
        by_tracer[r.tracer].push_back(&r);
    }
    std::string out;
    for (const std::string& name : order) {
        std::vector<double> speedup, sah, mrays;
        size_t refused = 0;
        for (const AnimateRow* r : by_tracer[name]) {
            if (!r->refused.empty()) {
                ++refused;
                continue;
            }
            if (r->refit_ms > 0) speedup.push_back(r->rebuild_ms / r->refit_ms);
            if (r->sah_refit > 0 && r->sah_rebuild > 0) sah.push_back(r->sah_refit / r->sah_rebuild);
            if (r->mrays_rebuild > 0) mrays.push_back(r->mrays_refit / r->mrays_rebuild);
        }
        out += "summary " + name + ": refit " + (speedup.empty() ? "-" : fixed(median(speedup), 1) + "x") +
               " faster than a rebuild (median over frames)";
        if (!sah.empty())
            out += ", SAH after refit " + fixed(median(sah), 3) + "x the rebuild's (worst " +
                   fixed(*std::max_element(sah.begin(), sah.end()), 3) + "x)";
        if (!mrays.empty())
            out += ", Mrays/s " + fixed(median(mrays), 3) + "x (worst " +
                   fixed(*std::min_element(mrays.begin(), mrays.end()), 3) + "x)";
        if (refused) out += ", " + std::to_string(refused) + " refits refused (rebuilt)";
        out += "\n";
    }
    // Refit time against Embree's, frame by frame (the figure: >= 1.0x).
    if (by_tracer.count("embree-refit"))
        for (const std::string& name : order) {
            if (name == "embree-refit") continue;
            std::vector<double> ratio;
            const auto& mine = by_tracer[name];
            const auto& theirs = by_tracer["embree-refit"];
            for (size_t i = 0; i < std::min(mine.size(), theirs.size()); ++i)
                if (mine[i]->refused.empty() && theirs[i]->refused.empty() && mine[i]->refit_ms > 0)
                    ratio.push_back(theirs[i]->refit_ms / mine[i]->refit_ms);
            if (!ratio.empty())
                out += "summary " + name + " refit time: " + fixed(median(ratio), 2) +
                       "x embree-refit's speed (embree ms / thicket ms, median over frames; above 1: faster)\n";
        }
    return out;
}

}  // namespace thicket
