// Whitted and the path tracer on scenes whose every pixel has a closed form computed here, with
// this file's own ray-plane geometry (issue 30): a point light seen in a tinted mirror (the mirror
// direction, the tint, I cos / d^2 on the surface it shows) and a Lambertian floor under a point
// light with a rectangular occluder between (the hard shadow's exact outline). The light transport
// of light_transport_test.cpp (a lit plane alone) is not repeated here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/render/bsdf.h"
#include "thicket/render/integrator.h"
#include "thicket/render/sampling.h"
#include "thicket/scene/scene.h"

#include "support/independent_math.h"

namespace thicket::closed_form_scenes_test {
namespace {


using testing::D3;
using testing::kPiD;
using testing::kWorkScale;
using testing::norm;

D3 d3(Vec3 v) { return {v.x, v.y, v.z}; }

/// Appends the rectangle y = `y`, x in [x0, x1], z in [z0, z1] as two triangles whose geometric
/// normal is +y when `up`, else -y.
void add_rect(TriangleMesh& mesh, float y, float x0, float x1, float z0, float z1, bool up) {
    const uint32_t a = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {{x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x1, y, z0}});
    // (a, b, c) with b - a along +z and c - a along +x and +z: (b - a) x (c - a) points along +y.
    const std::vector<uint32_t> tris = up ? std::vector<uint32_t>{a, a + 1, a + 2, a, a + 2, a + 3}
                                          : std::vector<uint32_t>{a, a + 2, a + 1, a, a + 3, a + 2};
    mesh.indices.insert(mesh.indices.end(), tris.begin(), tris.end());
}

/// A scene of rectangles (two primitives each, materials[k] for rectangle k) and point lights.
struct RectScene {
    Scene scene;
    RenderScene rs;
    std::unique_ptr<Accel> accel;
    Camera camera;
    int size;
    RectScene(Camera cam, int image_size) : camera(cam), size(image_size) {}
    void finish(const TriangleMesh& mesh, const std::vector<SurfaceMaterial>& materials) {
        scene.add_mesh(mesh);
        rs.scene = &scene;
        rs.materials = materials;
        for (uint32_t p = 0; p < mesh.triangle_count(); ++p) rs.prim_material.push_back(p / 2);
        accel = build_accel("bvh", scene);
    }
    TraceResult render(Integrator integrator, uint32_t spp, LightStrategy strategy = LightStrategy::Mis) const {
        TraceOptions o;
        o.strategy = strategy;
        o.width = o.height = size;
        o.spp = spp;
        o.seed = 9;
        o.progress = false;
        o.variance = true;
        return trace_image(rs, *accel, camera, integrator, o);
    }
    /// The camera ray through image point (px, py), origin and unit direction in double.
    void camera_ray(double px, double py, D3& org, D3& dir) const {
        const Ray r = camera.generate(float(px), float(py), size, size);
        org = d3(r.org);
        dir = d3(r.dir) * (1.0 / norm(d3(r.dir)));
    }
};

/// The radiance a Lambertian surface of albedo rho leaving point q, with unit normal along +y or
/// -y toward the light, receives from a point light of intensity I at `light`: rho / pi * I cos /
/// d^2, where cos = |light.y - q.y| / d.
double lambert_under_point(double rho, double I, D3 light, D3 q) {
    const double d = norm(light - q);
    return rho / kPiD * I * std::fabs(light.y - q.y) / (d * d * d);
}

// ---- A tinted mirror floor reflecting a Lambertian ceiling lit by a point light --------------

/// Floor y = 0: a mirror of reflectance kTint. Ceiling y = kCeiling: Lambertian (albedo kRho),
/// facing down. A point light of intensity kI between them. The camera looks down at the floor
/// only, so each pixel centre shows the ceiling point its mirrored ray reaches, lit directly;
/// Whitted adds nothing else (no diffuse interreflection).
struct MirrorScene : RectScene {
    static constexpr double kCeiling = 2.0, kRho = 0.5, kI = 10.0;
    static constexpr D3 kLight{0.3, 1.0, -0.5};
    static constexpr double kTint[3] = {0.9, 0.6, 0.3};
    MirrorScene() : RectScene(Camera({0, 1.2f, 3}, {0, 0, 0}, {0, 1, 0}, 30.0f), 12) {
        TriangleMesh mesh;
        const float e = 1000.0f;
        add_rect(mesh, 0.0f, -e, e, -e, e, true);
        add_rect(mesh, float(kCeiling), -e, e, -e, e, false);
        rs.point_lights.push_back({{float(kLight.x), float(kLight.y), float(kLight.z)}, Vec3{float(kI)}});
        finish(mesh, {mirror(Vec3{float(kTint[0]), float(kTint[1]), float(kTint[2])}), lambert(Vec3{float(kRho)})});
    }
    /// Radiance of channel c through image point (px, py), with the mirrored ray leaving the
    /// floor `lift` above it (0, or the most a renderer's self-intersection offset may add).
    double expected(double px, double py, int c, bool lifted) const {
        D3 o, d;
        camera_ray(px, py, o, d);
        EXPECT_LT(d.y, 0.0) << "the camera must see only the floor";
        D3 on_floor = o + d * (-o.y / d.y);
        // The renderer starts secondary rays up to 2e-4 max(1, |p|_inf) off the surface
        // (trace_common.h); twice that bounds how far its reflection may move along the ceiling.
        if (lifted) on_floor.y = 4e-4 * std::max({1.0, std::fabs(on_floor.x), std::fabs(on_floor.z)});
        const D3 mirrored{d.x, -d.y, d.z};  // reflection about the floor's normal
        const D3 on_ceiling = on_floor + mirrored * ((kCeiling - on_floor.y) / mirrored.y);
        return kTint[c] * lambert_under_point(kRho, kI, kLight, on_ceiling);
    }
};

TEST(ClosedFormScenes, WhittedShowsAPointLitCeilingInATintedMirror) {
    // One sample per pixel looks through its centre: no noise. Each channel lies between the
    // closed form for a reflection from the floor itself and from just above it (the renderer's
    // offset against self-intersection, which moves far ceiling points by up to 1e-3 relative),
    // widened by 1e-4 relative for float rounding.
    const MirrorScene s;
    const TraceResult r = s.render(Integrator::Whitted, 1);
    for (int j = 0; j < s.size; ++j)
        for (int i = 0; i < s.size; ++i) {
            const Vec3 got = r.radiance[size_t(j) * size_t(s.size) + size_t(i)];
            const float channels[3] = {got.x, got.y, got.z};
            for (int c = 0; c < 3; ++c) {
                const double exact = s.expected(i + 0.5, j + 0.5, c, false);
                const double lifted = s.expected(i + 0.5, j + 0.5, c, true);
                ASSERT_GT(exact, 0.0);
                EXPECT_GE(channels[c], std::min(exact, lifted) * (1 - 1e-4)) << "pixel " << i << " " << j << " channel " << c;
                EXPECT_LE(channels[c], std::max(exact, lifted) * (1 + 1e-4)) << "pixel " << i << " " << j << " channel " << c;
            }
        }
}

// ---- A Lambertian floor, a point light and a black rectangle casting a hard shadow ---------

/// Floor y = 0 (Lambertian, albedo kRho, facing up); a black rectangle at y = kOccluderY between
/// the floor and a point light at kLight. A floor point is dark exactly when its segment to the
/// light crosses the rectangle; the rectangle itself is black. The rectangle is off-centre from
/// the light, so a mirrored or misplaced shadow lands on other pixels.
struct ShadowScene : RectScene {
    static constexpr double kRho = 0.5, kI = 10.0, kOccluderY = 1.0;
    static constexpr D3 kLight{0.2, 2.0, 0.1};
    static constexpr double kX0 = -0.2, kX1 = 0.5, kZ0 = -0.4, kZ1 = 0.25;
    ShadowScene() : RectScene(Camera({0, 2.5f, 3}, {0.1f, 0, 0}, {0, 1, 0}, 40.0f), 16) {
        TriangleMesh mesh;
        const float e = 1000.0f;
        add_rect(mesh, 0.0f, -e, e, -e, e, true);
        add_rect(mesh, float(kOccluderY), float(kX0), float(kX1), float(kZ0), float(kZ1), true);
        rs.point_lights.push_back({{float(kLight.x), float(kLight.y), float(kLight.z)}, Vec3{float(kI)}});
        finish(mesh, {lambert(Vec3{float(kRho)}), lambert(Vec3{0.0f})});
    }
    /// Distance from (x, z) to the rectangle's outline, negative inside.
    static double signed_edge_distance(double x, double z) {
        const double dx = std::max(kX0 - x, x - kX1), dz = std::max(kZ0 - z, z - kZ1);
        if (dx <= 0 && dz <= 0) return std::max(dx, dz);
        return std::hypot(std::max(dx, 0.0), std::max(dz, 0.0));
    }
    enum class Seen { Occluder, Shadow, Lit };
    /// What the ray through (px, py) meets, its radiance, and how far (in the rectangle's plane)
    /// its decision lies from an outline: pixels within float reach of an edge are not judged.
    Seen trace(double px, double py, double& radiance, double& margin) const {
        D3 o, d;
        camera_ray(px, py, o, d);
        const D3 at_occluder = o + d * ((kOccluderY - o.y) / d.y);
        margin = signed_edge_distance(at_occluder.x, at_occluder.z);
        if (margin < 0) {
            radiance = 0;
            margin = -margin;
            return Seen::Occluder;
        }
        const D3 q = o + d * (-o.y / d.y);
        const D3 crossing = q + (kLight - q) * (kOccluderY / kLight.y);  // the segment at y = kOccluderY
        const double shadow = signed_edge_distance(crossing.x, crossing.z);
        margin = std::min(margin, std::fabs(shadow));
        if (shadow < 0) {
            radiance = 0;
            return Seen::Shadow;
        }
        radiance = lambert_under_point(kRho, kI, kLight, q);
        return Seen::Lit;
    }
};

TEST(ClosedFormScenes, WhittedCastsTheExactHardShadowOfARectangle) {
    // Pixel centres: lit floor to float rounding, the shadow and the black occluder exactly 0.
    // Pixels whose centre lies within 1e-3 (in the rectangle's plane) of an outline are left out.
    const ShadowScene s;
    const TraceResult r = s.render(Integrator::Whitted, 1);
    int counts[3] = {0, 0, 0};
    for (int j = 0; j < s.size; ++j)
        for (int i = 0; i < s.size; ++i) {
            double want = 0, margin = 0;
            const ShadowScene::Seen seen = s.trace(i + 0.5, j + 0.5, want, margin);
            if (margin < 1e-3) continue;
            ++counts[int(seen)];
            const Vec3 got = r.radiance[size_t(j) * size_t(s.size) + size_t(i)];
            EXPECT_NEAR(got.x, want, 1e-4 * want) << "pixel " << i << " " << j << " (" << int(seen) << ")";
            EXPECT_EQ(got.x, got.z) << "grey light on a grey floor";
        }
    // The scene is framed so that every case has pixels to judge.
    EXPECT_GE(counts[int(ShadowScene::Seen::Occluder)], 6);
    EXPECT_GE(counts[int(ShadowScene::Seen::Shadow)], 6);
    EXPECT_GE(counts[int(ShadowScene::Seen::Lit)], 150);
}

/// Every pixel of the path-traced ShadowScene `r` against the closed form's mean over the pixel.
void expect_shadow_pixel_means(const ShadowScene& s, const TraceResult& r);

TEST(ClosedFormScenes, PathTracerCastsTheSameShadowOnAverageOverEachPixel) {
    // Jittered samples converge to the closed form's mean over the pixel (32 x 32 midpoints here).
    // Nothing reflects light back: the occluder is black and a plane cannot see itself. Bound per
    // pixel: 5 SE (from the samples' variance) plus 1e-3 relative, plus, where an outline crosses
    // the pixel, 2/32 of its brightest point (the midpoint rule's error on a step); and the image
    // sum within 4 SE.
    const ShadowScene s;
    for (const LightStrategy strategy : {LightStrategy::Mis, LightStrategy::LightOnly}) {
        SCOPED_TRACE(strategy == LightStrategy::Mis ? "MIS" : "light sampling only");
        expect_shadow_pixel_means(s, s.render(Integrator::Path, 64 / kWorkScale, strategy));
    }
    // BSDF sampling alone never finds a point light (integrator.h): every pixel black.
    const TraceResult dark = s.render(Integrator::Path, 4, LightStrategy::BsdfOnly);
    for (const Vec3& c : dark.radiance) ASSERT_EQ(c, Vec3{});
}

void expect_shadow_pixel_means(const ShadowScene& s, const TraceResult& r) {
    constexpr int g = 32;
    double got_sum = 0, want_sum = 0, var_sum = 0;
    int edge_pixels = 0;
    for (int j = 0; j < s.size; ++j)
        for (int i = 0; i < s.size; ++i) {
            double sum = 0, brightest = 0;
            bool cases[3] = {false, false, false};
            for (int a = 0; a < g; ++a)
                for (int b = 0; b < g; ++b) {
                    double L = 0, margin = 0;
                    cases[int(s.trace(i + (a + 0.5) / g, j + (b + 0.5) / g, L, margin))] = true;
                    sum += L;
                    brightest = std::max(brightest, L);
                }
            const double want = sum / (g * g);
            const bool edge = int(cases[0]) + int(cases[1]) + int(cases[2]) > 1;
            edge_pixels += edge;
            const size_t k = size_t(j) * size_t(s.size) + size_t(i);
            const double var = double(r.lum_variance[k]) / r.spp;
            const double bound = 5.0 * std::sqrt(var) + 1e-3 * want + (edge ? 2.0 * brightest / g : 0.0);
            EXPECT_NEAR(luminance(r.radiance[k]), want, bound) << "pixel " << i << " " << j;
            got_sum += luminance(r.radiance[k]);
            want_sum += want;
            var_sum += var;
        }
    EXPECT_GE(edge_pixels, 8);
    EXPECT_NEAR(got_sum, want_sum, 4.0 * std::sqrt(var_sum) + 1e-3 * want_sum);
}

}  // namespace
}  // namespace thicket::closed_form_scenes_test
