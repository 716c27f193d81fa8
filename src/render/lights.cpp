#include "thicket/render/lights.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <set>

#include "thicket/core/error.h"
#include "thicket/render/sampling.h"
#include "thicket/scene/material_ranges.h"

namespace thicket {

namespace {

std::string material_label(const RenderScene& rs, uint32_t index) {
    const std::string& name = rs.materials[index].name;
    std::string label(1, name.empty() ? '#' : '\'');  // built by appending: GCC 12 warns (-Wrestrict) on "#" + string
    label += name.empty() ? std::to_string(index) : name + "'";
    return label;
}

/// Writes `message` to stderr the first time this process sees it: a LightSet is built for every
/// pass of a progressive render, and its note should appear once.
void say_once(const std::string& message) {
    static std::mutex mutex;
    static std::set<std::string> said;
    const std::lock_guard lock(mutex);
    if (said.insert(message).second) std::cerr << message << '\n';
}

/// Twice the area of triangle (a, b, c), in double: float coordinates whose differences overflow
/// float (and a cross product that overflows float) still give a finite area.
double double_area(Vec3 a, Vec3 b, Vec3 c) {
    const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    return std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

}  // namespace

void check_emitters(const RenderScene& rs) {
    for (uint32_t i = 0; i < rs.materials.size(); ++i) {
        const Vec3 e = rs.materials[i].emission;
        for (int c = 0; c < 3; ++c)
            if (const std::string why = material_value_problem(MaterialParam::Emission, e[c]); !why.empty())
                throw Error("render: material " + material_label(rs, i) + ": emission[" + std::to_string(c) + "]: " + why);
    }
    for (size_t i = 0; i < rs.point_lights.size(); ++i) {
        const Vec3 v = rs.point_lights[i].intensity;
        for (int c = 0; c < 3; ++c)
            if (!(v[c] >= 0.0f && double(v[c]) <= kMaxPointIntensity)) {
                char got[32];
                std::snprintf(got, sizeof got, "%g", double(v[c]));
                throw Error("render: point light " + std::to_string(i) + ": intensity[" + std::to_string(c) +
                            "]: must be a number from 0 to 1e+20, got " + got);
            }
    }
}

LightSet::LightSet(const RenderScene& rs) {
    check_emitters(rs);
    const Scene& scene = *rs.scene;
    // With instances, hits carry flattened ids and the prototypes' positions are not the world's:
    // emissive instanced surfaces are seen where rays hit them but not sampled as lights.
    const uint32_t sampled = scene.instances.empty() ? uint32_t(scene.primitive_count()) : 0;
    light_of_prim_.assign(sampled, kNoPrim);
    std::vector<double> power;
    for (uint32_t p = 0; p < sampled; ++p) {
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
            const double one_side = 0.5 * double_area(l.a, scene.mesh.vertex(ref.index, 1), scene.mesh.vertex(ref.index, 2));
            l.radius_or_area = float(one_side);  // infinite for a float-overflowing triangle: its pdf is 0
            area = one_side * (l.two_sided ? 2.0 : 1.0);
        } else if (const auto* s = std::get_if<Sphere>(&scene.shapes[ref.index])) {
            l.kind = Kind::Sphere;
            l.a = s->center;
            l.radius_or_area = s->radius;
            area = 4.0 * double(kPi) * double(s->radius) * double(s->radius);
        } else {
            // Other emissive shapes glow when hit but are not sampled: a scene lit only by them
            // converges slowly, so say so.
            say_once("render: material " + material_label(rs, rs.prim_material[p]) + " emits on a " +
                     shape_name(scene.shapes[ref.index]) +
                     ", which is not sampled as a light (only triangles and spheres are); it glows where rays hit it");
            continue;
        }
        if (!(area > 0.0)) continue;
        light_of_prim_[p] = uint32_t(lights_.size());
        lights_.push_back(l);
        // Finite: area < 1e78 in double for float coordinates, luminance <= kMaxEmission (checked).
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
    total_power_ = total;
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


std::string add_automatic_light(RenderScene& rs, const Accel& accel, const Camera& camera, int width, int height) {
    if (!LightSet(rs).empty()) return "";
    if (width < 1 || height < 1) throw Error("automatic light: image size must be at least 1x1");
    // What the camera sees, not the scene's bounds, sets the distance: a huge ground sphere puts
    // the bounds' centre a thousand units away while the camera looks at things a few units off.
    constexpr int kProbe = 32;
    std::vector<float> distances;
    for (int j = 0; j < kProbe; ++j)
        for (int i = 0; i < kProbe; ++i) {
            const Ray ray = camera.generate((float(i) + 0.5f) * float(width) / kProbe,
                                            (float(j) + 0.5f) * float(height) / kProbe, width, height);
            const Hit hit = accel.intersect(ray);
            if (hit.found() && std::isfinite(hit.t) && hit.t > 0.0f) distances.push_back(hit.t);
        }
    float d = 0.0f;
    if (!distances.empty()) {
        const auto quarter = distances.begin() + std::ptrdiff_t(distances.size() / 4);
        std::nth_element(distances.begin(), quarter, distances.end());
        d = *quarter;
    } else {
        d = length(rs.scene->bounds().center() - camera.position());
    }
    if (!std::isfinite(d) || d < 1e-3f) d = 1e-3f;
    PointLight light;
    light.position = camera.position() + camera.up() * (0.05f * d);
    // Radiance of a white (albedo 0.8) Lambertian facing the light at distance d: 0.8 / pi * I / d^2 = 0.5.
    light.intensity = Vec3{float(std::min(2.0 * double(d) * double(d), kMaxPointIntensity))};
    rs.point_lights.push_back(light);
    char line[200];
    std::snprintf(line, sizeof line,
                  "render: the scene has no light: added a point light at the camera, intensity %g (2 d^2, d = %g: "
                  "the nearer quarter of the visible surfaces)",
                  double(light.intensity.x), double(d));
    std::cerr << line << '\n';
    return line;
}

}  // namespace thicket
