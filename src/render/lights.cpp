#include "thicket/render/lights.h"

#include <algorithm>
#include <cmath>

#include "thicket/render/sampling.h"

namespace thicket {

LightSet::LightSet(const RenderScene& rs) {
    const Scene& scene = *rs.scene;
    light_of_prim_.assign(scene.primitive_count(), kNoPrim);
    std::vector<double> power;
    for (uint32_t p = 0; p < scene.primitive_count(); ++p) {
        const SurfaceMaterial& m = rs.material(p);
        if (!m.emissive()) continue;
        const PrimRef ref = scene.locate(p);
        Light l{};
        l.prim = p;
        l.radiance = m.emission;
        l.two_sided = m.two_sided;
        double area = 0.0;
        if (!ref.shape) {
            l.kind = Kind::Triangle;
            l.a = scene.mesh.vertex(ref.index, 0);
            l.e1 = scene.mesh.vertex(ref.index, 1) - l.a;
            l.e2 = scene.mesh.vertex(ref.index, 2) - l.a;
            l.radius_or_area = 0.5f * length(cross(l.e1, l.e2));
            area = l.radius_or_area * (l.two_sided ? 2.0 : 1.0);
        } else if (const auto* s = std::get_if<Sphere>(&scene.shapes[ref.index])) {
            l.kind = Kind::Sphere;
            l.a = s->center;
            l.radius_or_area = s->radius;
            area = 4.0 * double(kPi) * double(s->radius) * double(s->radius);
        } else {
            continue;  // other emissive shapes glow when hit but are not sampled
        }
        if (!(area > 0.0)) continue;
        light_of_prim_[p] = uint32_t(lights_.size());
        lights_.push_back(l);
        power.push_back(double(kPi) * area * std::max(1e-9, double(luminance(m.emission))));
    }
    for (const PointLight& pl : rs.point_lights) {
        Light l{};
        l.kind = Kind::Point;
        l.prim = kNoPrim;
        l.a = pl.position;
        l.radiance = pl.intensity;
        lights_.push_back(l);
        power.push_back(4.0 * double(kPi) * std::max(1e-9, double(luminance(pl.intensity))));
    }
    double total = 0.0;
    for (double w : power) total += w;
    double running = 0.0;
    for (double w : power) {
        running += w;
        cdf_.push_back(float(running / total));
    }
    if (!cdf_.empty()) cdf_.back() = 1.0f;
}

float LightSet::pick_probability(size_t i) const { return cdf_[i] - (i == 0 ? 0.0f : cdf_[i - 1]); }

bool LightSet::sample(Vec3 p, float u_pick, float u0, float u1, LightSample& out) const {
    if (cdf_.empty()) return false;
    const size_t i = std::min(size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u_pick) - cdf_.begin()), cdf_.size() - 1);
    const float pick = pick_probability(i);
    if (!(pick > 0.0f)) return false;
    const Light& l = lights_[i];
    if (l.kind == Kind::Point) {
        const Vec3 d = l.a - p;
        const float d2 = dot(d, d);
        if (!(d2 > 0.0f)) return false;
        out.distance = std::sqrt(d2);
        out.wi = d / out.distance;
        out.radiance = l.radiance / d2;
        out.pdf = pick;
        out.delta = true;
        return true;
    }
    out.delta = false;
    if (l.kind == Kind::Triangle) {
        float b1 = 0, b2 = 0;
        sample_triangle(u0, u1, b1, b2);
        const Vec3 y = l.a + l.e1 * b1 + l.e2 * b2;
        const Vec3 n = normalize(cross(l.e1, l.e2));
        const Vec3 d = y - p;
        const float d2 = dot(d, d);
        if (!(d2 > 0.0f)) return false;
        out.distance = std::sqrt(d2);
        out.wi = d / out.distance;
        const float cos_l = -dot(n, out.wi);  // > 0: p is on the emitting (front) side
        if (!(l.two_sided ? cos_l != 0.0f : cos_l > 0.0f)) return false;
        out.radiance = l.radiance;
        out.pdf = pick * d2 / (std::fabs(cos_l) * l.radius_or_area);
        return std::isfinite(out.pdf);
    }
    // Sphere.
    const float r = l.radius_or_area;
    const Vec3 to_c = l.a - p;
    const float dc2 = dot(to_c, to_c);
    if (dc2 > r * r * 1.0001f) {
        // Outside: uniform in the subtended cone; 1 - cos_max = (r^2/d^2) / (1 + cos_max).
        const float dc = std::sqrt(dc2);
        const float sin2 = r * r / dc2;
        const float cos_max = std::sqrt(std::fmax(0.0f, 1.0f - sin2));
        const float one_minus = sin2 / (1.0f + cos_max);
        const Vec3 axis = to_c / dc;
        const Vec3 local = sample_uniform_cone(u0, u1, one_minus);
        out.wi = normalize(Frame(axis).to_world(local));
        // Distance to the near intersection along wi.
        const float b = dot(to_c, out.wi);
        const float h2 = std::fmax(0.0f, r * r - (dc2 - b * b));
        out.distance = b - std::sqrt(h2);
        if (!(out.distance > 0.0f)) return false;
        out.radiance = l.radiance;
        out.pdf = pick / (2.0f * kPi * one_minus);
        return std::isfinite(out.pdf);
    }
    // Inside (or on) the sphere: a point uniform on its surface.
    const Vec3 nrm = sample_uniform_sphere(u0, u1);
    const Vec3 y = l.a + nrm * r;
    const Vec3 d = y - p;
    const float d2 = dot(d, d);
    if (!(d2 > 0.0f)) return false;
    out.distance = std::sqrt(d2);
    out.wi = d / out.distance;
    const float cos_l = std::fabs(dot(nrm, out.wi));
    if (!(cos_l > 0.0f) || !l.two_sided) return false;  // the inside only glows for two-sided emitters
    out.radiance = l.radiance;
    out.pdf = pick * d2 / (cos_l * 4.0f * kPi * r * r);
    return std::isfinite(out.pdf);
}

float LightSet::pdf(Vec3 p, Vec3 wi, uint32_t prim, Vec3 y, Vec3 n_y) const {
    if (prim >= light_of_prim_.size() || light_of_prim_[prim] == kNoPrim) return 0.0f;
    const size_t i = light_of_prim_[prim];
    const Light& l = lights_[i];
    const float pick = pick_probability(i);
    if (l.kind == Kind::Triangle) {
        const float cos_l = -dot(n_y, wi);
        if (!(l.two_sided ? cos_l != 0.0f : cos_l > 0.0f)) return 0.0f;
        const Vec3 d = y - p;
        return pick * dot(d, d) / (std::fabs(cos_l) * l.radius_or_area);
    }
    const float r = l.radius_or_area;
    const Vec3 to_c = l.a - p;
    const float dc2 = dot(to_c, to_c);
    if (dc2 > r * r * 1.0001f) {
        const float sin2 = r * r / dc2;
        const float cos_max = std::sqrt(std::fmax(0.0f, 1.0f - sin2));
        return pick / (2.0f * kPi * (sin2 / (1.0f + cos_max)));
    }
    if (!l.two_sided) return 0.0f;
    const float cos_l = std::fabs(dot(n_y, wi));
    if (!(cos_l > 0.0f)) return 0.0f;
    const Vec3 d = y - p;
    return pick * dot(d, d) / (cos_l * 4.0f * kPi * r * r);
}

}  // namespace thicket
