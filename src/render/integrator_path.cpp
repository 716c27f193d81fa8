// The path tracer, wavefront style: a tile's paths advance together, one batch of bounce rays
// and one batch of shadow rays per segment, so the structure's batch API (and bvh8's packets for
// the coherent camera rays) does the tracing.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "thicket/core/error.h"
#include "thicket/render/integrator.h"
#include "thicket/render/lights.h"
#include "thicket/render/sampling.h"
#include "trace_common.h"
#include "thicket/util/parallel.h"
#include "thicket/util/progress.h"

namespace thicket {

namespace {

struct PathState {
    Rng rng{0, 0};
    Vec3 beta{1.0f};       // throughput
    Vec3 L{};              // radiance gathered so far
    Vec3 prev_p{};         // where the current ray left
    float prev_pdf = 0.0f; // BSDF density of the current ray's direction
    bool prev_delta = true;// the current ray came from the camera or a delta lobe
    float eta_scale = 1.0f;// undoes the 1/eta^2 radiance scaling of refractions for Russian roulette
    uint32_t depth = 0;    // segments traced before the current ray
};

struct Shadow {
    uint32_t path;
    Vec3 contribution;
};

}  // namespace

TraceResult trace_path(const RenderScene& rs, const Accel& accel, const Camera& camera, const TraceOptions& options) {
    TraceResult result = begin_trace(rs, options);
    const int W = options.width, H = options.height;
    const LightSet lights(rs);
    const Scene& scene = *rs.scene;
    const bool use_light = options.strategy != LightStrategy::BsdfOnly;
    const bool use_bsdf_hits = options.strategy != LightStrategy::LightOnly;

    const Tiling tiling{W, H};
    std::atomic<uint64_t> rays_traced{0};
    Progress progress("render", uint64_t(W) * uint64_t(H) * options.spp, "samples", options.progress);
    progress.show_rate_of("rays");
    const auto start = std::chrono::steady_clock::now();

    parallel_for(tiling.count(), 1, options.threads, [&](size_t tile_begin, size_t tile_end) {
        std::vector<PathState> paths;
        std::vector<uint32_t> pixel_of;  // image index of each tile pixel
        std::vector<uint32_t> active, next_active;
        std::vector<Ray> rays, shadow_rays;
        std::vector<Hit> hits;
        std::vector<Shadow> shadows;
        std::vector<uint8_t> blocked;
        BatchOptions batch;
        batch.threads = 1;  // the tiles are the parallel loop
        uint64_t local_rays = 0, reported_rays = 0;
        for (size_t tile = tile_begin; tile < tile_end; ++tile) {
            tiling.pixels(tile, pixel_of);
            const uint32_t np = uint32_t(pixel_of.size());
            const uint32_t wave_spp = std::max<uint32_t>(1, kTraceWave / np);
            for (uint32_t s0 = 0; s0 < options.spp; s0 += wave_spp) {
                const uint32_t ns = std::min(wave_spp, options.spp - s0);
                const uint32_t n = ns * np;
                paths.assign(n, PathState{});
                rays.resize(n);
                active.resize(n);
                for (uint32_t k = 0; k < n; ++k) {
                    const uint32_t pix = pixel_of[k % np];
                    const uint32_t sample = options.first_sample + s0 + k / np;
                    PathState& ps = paths[k];
                    ps.rng = Rng::for_sample(options.seed, pix, sample);
                    const float jx = ps.rng.uniform(), jy = ps.rng.uniform();
                    rays[k] = camera.generate(float(pix % uint32_t(W)) + jx, float(pix / uint32_t(W)) + jy, W, H);
                    active[k] = k;
                }
                batch.coherent = true;
                while (!active.empty()) {
                    hits.resize(active.size());
                    accel.intersect(std::span<const Ray>(rays.data(), active.size()), hits, batch);
                    batch.coherent = false;
                    local_rays += active.size();
                    shadows.clear();
                    shadow_rays.clear();
                    next_active.clear();
                    for (size_t a = 0; a < active.size(); ++a) {
                        const uint32_t k = active[a];
                        PathState& ps = paths[k];
                        const Ray& ray = rays[a];
                        const Hit& hit = hits[a];
                        if (!hit.found()) continue;  // no environment light: the path ends
                        const SurfaceMaterial& m = rs.material(hit.prim);
                        const Vec3 p = ray.org + ray.dir * hit.t;
                        const Vec3 n = scene.normal(ray, hit);
                        if (n == Vec3{}) continue;
                        const Vec3 wo = -ray.dir;
                        // Emission found by this ray.
                        if (m.emissive() && (m.two_sided || dot(n, wo) > 0.0f)) {
                            if (ps.prev_delta || !use_light) {
                                ps.L += ps.beta * m.emission;
                            } else if (use_bsdf_hits) {
                                const float light_pdf = lights.pdf(ps.prev_p, ray.dir, hit.prim, p, n);
                                ps.L += ps.beta * m.emission * power_heuristic(ps.prev_pdf, light_pdf);
                            }
                        }
                        if (!m.scatters() || ps.depth + 1 >= options.max_depth) continue;
                        // Next event estimation.
                        if (use_light && !m.delta() && !lights.empty()) {
                            const float u_pick = ps.rng.uniform(), u0 = ps.rng.uniform(), u1 = ps.rng.uniform();
                            LightSample ls;
                            if (lights.sample(p, u_pick, u0, u1, ls)) {
                                const Vec3 f = eval_bsdf(m, n, wo, ls.wi);
                                if (f != Vec3{} && ls.pdf > 0.0f) {
                                    float w = 1.0f;
                                    if (!ls.delta && use_bsdf_hits) w = power_heuristic(ls.pdf, pdf_bsdf(m, n, wo, ls.wi));
                                    shadows.push_back({k, ps.beta * f * ls.radiance * (w / ls.pdf)});
                                    shadow_rays.push_back(shadow_ray(p, n, ls.wi, ls.distance));
                                }
                            }
                        }
                        // BSDF sampling: the path's next segment.
                        const float u0 = ps.rng.uniform(), u1 = ps.rng.uniform(), u2 = ps.rng.uniform();
                        BsdfSample bs;
                        if (!sample_bsdf(m, n, wo, u0, u1, u2, bs)) continue;
                        ps.beta = ps.beta * bs.weight;
                        if (m.kind == SurfaceKind::Dielectric && bs.weight.x > 0.0f) ps.eta_scale /= bs.weight.x;
                        ps.prev_pdf = bs.pdf;
                        ps.prev_delta = bs.delta;
                        ps.prev_p = p;
                        ++ps.depth;
                        if (ps.depth >= options.rr_depth) {
                            // Survival from the throughput, not counting refraction's radiance scaling
                            // (a path inside glass is not dimmer, only compressed).
                            const float q = std::min(0.95f, max_component(ps.beta) * ps.eta_scale);
                            if (!(ps.rng.uniform() < q)) continue;
                            ps.beta = ps.beta / q;
                        }
                        next_active.push_back(k);
                        rays[next_active.size() - 1] = spawn_ray(p, n, bs.wi);  // a <= index: not read again
                    }
                    if (!shadow_rays.empty()) {
                        blocked.resize(shadow_rays.size());
                        accel.occluded(shadow_rays, blocked, batch);
                        local_rays += shadow_rays.size();
                        for (size_t i = 0; i < shadows.size(); ++i)
                            if (!blocked[i]) paths[shadows[i].path].L += shadows[i].contribution;
                    }
                    active.swap(next_active);
                }
                // Sum in sample order per pixel: the same order whatever thread ran the tile.
                for (uint32_t k = 0; k < n; ++k) add_sample(result, pixel_of[k % np], paths[k].L, options.variance);
                progress.advance(n);
                progress.count_also(local_rays - reported_rays);
                reported_rays = local_rays;
            }
        }
        rays_traced += local_rays;
    });
    progress.finish();
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.rays = rays_traced.load();
    finish_trace(result);
    return result;
}

}  // namespace thicket
