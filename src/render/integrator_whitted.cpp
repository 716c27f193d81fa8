// The Whitted ray tracer (Whitted 1980): at each hit, direct light from every light through one
// shadow ray, plus the mirror and refracted rays traced recursively.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include "thicket/render/integrator.h"
#include "thicket/render/sampling.h"
#include "thicket/util/parallel.h"
#include "thicket/util/progress.h"
#include "trace_common.h"

namespace thicket {

namespace {

/// A light as Whitted saw it: a point, with the intensity toward direction -wi.
struct WhittedLight {
    Vec3 position;
    Vec3 radiance;      // area lights: radiance; point lights: intensity
    Vec3 normal;        // area triangles: the emitting side's normal; else zero
    float area = 0.0f;  // 0: a point light (or a sphere: see sphere_radius)
    float sphere_radius = 0.0f;
};

class Whitted {
public:
    Whitted(const RenderScene& rs, const Accel& accel, uint32_t max_depth)
        : rs_(rs), accel_(accel), max_depth_(std::min<uint32_t>(max_depth, 16)) {
        // The emissive triangles of one material are one light (a quad light casts one shadow, not
        // two): a point at their area-weighted centre, with their total area and mean normal.
        const Scene& scene = *rs.scene;
        std::vector<WhittedLight> by_material(rs.materials.size());
        std::vector<Vec3> weighted_centre(rs.materials.size()), weighted_normal(rs.materials.size());
        // With instances the prototypes' positions are not the world's: emissive instanced
        // surfaces are seen where rays hit them, not made into lights (as LightSet does).
        for (uint32_t p = 0; scene.instances.empty() && p < scene.primitive_count(); ++p) {
            const SurfaceMaterial& m = rs.material(p);
            if (!m.emissive()) continue;
            const PrimRef ref = scene.locate(p);
            if (!ref.shape) {
                const Vec3 a = scene.mesh.vertex(ref.index, 0), b = scene.mesh.vertex(ref.index, 1),
                           c = scene.mesh.vertex(ref.index, 2);
                const Vec3 cr = cross(b - a, c - a);
                const float area = 0.5f * length(cr);
                if (!(area > 0.0f)) continue;
                const uint32_t id = rs.prim_material[p];
                by_material[id].radiance = m.emission;
                by_material[id].area += area;
                weighted_centre[id] += (a + b + c) * (area / 3.0f);
                weighted_normal[id] += cr * 0.5f;
            } else if (const auto* s = std::get_if<Sphere>(&scene.shapes[ref.index])) {
                WhittedLight l;
                l.radiance = m.emission;
                l.position = s->center;
                l.sphere_radius = s->radius;
                lights_.push_back(l);
            }
        }
        for (size_t id = 0; id < by_material.size(); ++id) {
            WhittedLight& l = by_material[id];
            if (!(l.area > 0.0f)) continue;
            l.position = weighted_centre[id] / l.area;
            const float len = length(weighted_normal[id]);
            if (!(len > 0.0f)) continue;  // opposite faces cancel: no single emitting side
            l.normal = weighted_normal[id] / len;
            l.area = len;  // the projected area along the mean normal
            lights_.push_back(l);
        }
        for (const PointLight& pl : rs.point_lights) lights_.push_back({pl.position, pl.intensity, {}, 0.0f, 0.0f});
    }

    Vec3 trace(const Ray& ray, uint32_t depth, uint64_t& rays) const {
        ++rays;
        const Hit hit = accel_.intersect(ray);
        if (!hit.found()) return {};
        const SurfaceMaterial& m = rs_.material(hit.prim);
        const Vec3 p = ray.org + ray.dir * hit.t;
        const Vec3 n = rs_.scene->normal(ray, hit);
        if (n == Vec3{}) return {};
        const Vec3 wo = -ray.dir;
        Vec3 L{};
        if (m.emissive() && (m.two_sided || dot(n, wo) > 0.0f)) L += m.emission;
        if (depth + 1 >= max_depth_) return L;
        if (m.kind == SurfaceKind::Dielectric) {
            const float cos_o = dot(n, wo);
            const bool entering = cos_o > 0.0f;
            const Vec3 nf = entering ? n : -n;
            const float eta = entering ? m.ior : 1.0f / m.ior;
            const float cos_i = std::fabs(cos_o);
            const float R = fresnel_dielectric(cos_i, eta);
            L += trace(spawn_ray(p, n, reflect(wo, nf)), depth + 1, rays) * R;
            if (R < 1.0f) {
                const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
                const float cos_t = std::sqrt(std::fmax(0.0f, 1.0f - sin2_t));
                const Vec3 wt = normalize(-wo / eta + nf * (cos_i / eta - cos_t));
                L += trace(spawn_ray(p, n, wt), depth + 1, rays) * ((1.0f - R) / (eta * eta));
            }
            return L;
        }
        if (m.kind == SurfaceKind::Mirror) {
            const Vec3 nf = dot(n, wo) >= 0.0f ? n : -n;
            return L + trace(spawn_ray(p, n, reflect(wo, nf)), depth + 1, rays) * m.specular;
        }
        // Diffuse and glossy: hard shadows from every light.
        for (const WhittedLight& l : lights_) {
            Vec3 d = l.position - p;
            float dist = length(d);
            if (!(dist > 0.0f)) continue;
            Vec3 wi = d / dist;
            Vec3 intensity = l.radiance;  // toward p, W/sr
            if (l.area > 0.0f) {
                const float cos_l = -dot(l.normal, wi);
                if (!(cos_l > 0.0f)) continue;
                intensity = l.radiance * (l.area * cos_l);
            } else if (l.sphere_radius > 0.0f) {
                if (!(dist > l.sphere_radius)) continue;
                intensity = l.radiance * (kPi * l.sphere_radius * l.sphere_radius);
                dist -= l.sphere_radius;  // the shadow ray stops at the sphere's near side
            }
            const Vec3 f = eval_bsdf(m, n, wo, wi);
            if (f == Vec3{}) continue;
            ++rays;
            if (accel_.occluded(shadow_ray(p, n, wi, dist))) continue;
            const float d_centre = length(d);
            L += f * intensity / (d_centre * d_centre);
        }
        if (m.kind == SurfaceKind::Glossy) {
            const Vec3 nf = dot(n, wo) >= 0.0f ? n : -n;
            L += trace(spawn_ray(p, n, reflect(wo, nf)), depth + 1, rays) * m.specular;
        }
        return L;
    }

private:
    const RenderScene& rs_;
    const Accel& accel_;
    uint32_t max_depth_;
    std::vector<WhittedLight> lights_;
};

}  // namespace

TraceResult trace_whitted(const RenderScene& rs, const Accel& accel, const Camera& camera, const TraceOptions& options) {
    TraceResult result = begin_trace(rs, options);
    const int W = options.width, H = options.height;
    const Whitted whitted(rs, accel, options.max_depth);
    const Tiling tiling{W, H};
    std::atomic<uint64_t> rays_traced{0};
    Progress progress("render", uint64_t(W) * uint64_t(H) * options.spp, "samples", options.progress);
    const auto start = std::chrono::steady_clock::now();
    parallel_for(tiling.count(), 1, options.threads, [&](size_t tile_begin, size_t tile_end) {
        std::vector<uint32_t> pixel_of;
        uint64_t rays = 0;
        for (size_t tile = tile_begin; tile < tile_end; ++tile) {
            tiling.pixels(tile, pixel_of);
            for (uint32_t pix : pixel_of)
                for (uint32_t s = 0; s < options.spp; ++s) {
                    const uint32_t sample = options.first_sample + s;
                    // One sample per pixel looks through the centre; more are jittered (anti-aliasing).
                    float jx = 0.5f, jy = 0.5f;
                    if (options.spp > 1 || sample > 0) {
                        Rng rng = Rng::for_sample(options.seed, pix, sample);
                        jx = rng.uniform();
                        jy = rng.uniform();
                    }
                    const Ray ray = camera.generate(float(pix % uint32_t(W)) + jx, float(pix / uint32_t(W)) + jy, W, H);
                    add_sample(result, pix, whitted.trace(ray, 0, rays), options.variance);
                }
            progress.advance(pixel_of.size() * options.spp);
        }
        rays_traced += rays;
    });
    progress.finish();
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.rays = rays_traced.load();
    finish_trace(result);
    return result;
}

Integrator parse_integrator(std::string_view name) {
    if (name == "path") return Integrator::Path;
    if (name == "whitted") return Integrator::Whitted;
    throw Error("unknown integrator '" + std::string(name) + "' (choose path or whitted)");
}

const char* integrator_name(Integrator integrator) { return integrator == Integrator::Path ? "path" : "whitted"; }

TraceResult trace_image(const RenderScene& rs, const Accel& accel, const Camera& camera, Integrator integrator,
                        const TraceOptions& options) {
    return integrator == Integrator::Path ? trace_path(rs, accel, camera, options)
                                          : trace_whitted(rs, accel, camera, options);
}

void accumulate(TraceResult& total, const TraceResult& more) {
    if (total.width != more.width || total.height != more.height || total.sum.size() != more.sum.size())
        throw Error("accumulate: the two renders differ in size");
    for (size_t i = 0; i < total.sum.size(); ++i) total.sum[i] += more.sum[i];
    if (total.lum_sum2.size() == more.lum_sum2.size())
        for (size_t i = 0; i < total.lum_sum2.size(); ++i) total.lum_sum2[i] += more.lum_sum2[i];
    else
        total.lum_sum2.clear();
    total.spp += more.spp;
    total.rays += more.rays;
    total.seconds += more.seconds;
    finish_trace(total);
}

}  // namespace thicket
