// Validation of the light-transport integrators: furnaces with closed-form answers, the dielectric's
// energy balance, agreement of the three direct-light strategies, thread-count determinism and the
// Cornell box against a committed converged reference. Every statistical test has a fixed seed
// and states its bound in standard errors (SE) estimated from the samples themselves.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <memory>
#include <fstream>
#include <string>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/render/bsdf.h"
#include "thicket/render/integrator.h"
#include "thicket/render/sampling.h"
#include "thicket/scene/scene.h"

#include "support/independent_math.h"

namespace thicket::path_tracer_test {
namespace {

using testing::kWorkScale;

/// Mean luminance over the pixels in `mask` (all when empty) and its standard error.
struct Estimate {
    double mean = 0, se = 0;
};
Estimate image_estimate(const TraceResult& r, const std::vector<size_t>& pixels) {
    double sum = 0, var = 0;
    for (size_t i : pixels) {
        sum += luminance(r.radiance[i]);
        var += double(r.lum_variance[i]) / r.spp;
    }
    const double n = double(pixels.size());
    return {sum / n, std::sqrt(var) / n};
}
std::vector<size_t> all_pixels(const TraceResult& r) {
    std::vector<size_t> v(size_t(r.width) * size_t(r.height));
    for (size_t i = 0; i < v.size(); ++i) v[i] = i;
    return v;
}

/// A furnace: a two-sided emitter sphere of radius 10 (radiance 1, black) around `inner` at the
/// origin (radius 1), seen from (0, 0, 4).
struct Furnace {
    Scene scene;
    RenderScene rs;
    std::unique_ptr<Accel> accel;
    Camera camera{{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30.0f};
    explicit Furnace(const SurfaceMaterial& inner) {
        scene.add_shape(Sphere{{0, 0, 0}, 10.0f});
        scene.add_shape(Sphere{{0, 0, 0}, 1.0f});
        SurfaceMaterial emitter = lambert(Vec3{0.0f}, Vec3{1.0f});
        emitter.two_sided = true;
        rs.scene = &scene;
        rs.materials = {emitter, inner};
        rs.prim_material = {0, 1};
        accel = build_accel("bvh", scene);
    }
    TraceResult render(uint32_t spp, LightStrategy strategy = LightStrategy::Mis, uint64_t seed = 1) const {
        TraceOptions o;
        o.width = o.height = 16;
        o.spp = spp;
        o.seed = seed;
        o.strategy = strategy;
        o.progress = false;
        o.variance = true;
        return trace_path(rs, *accel, camera, o);
    }
};

/// Pixels whose whole square sees the inner sphere (its four corners do: the sphere is convex).
std::vector<size_t> inner_pixels(const Furnace& f, int size) {
    std::vector<size_t> v;
    auto inner = [&](float px, float py) {
        const Hit h = f.accel->intersect(f.camera.generate(px, py, size, size));
        return h.found() && f.scene.locate(h.prim).index == 1;
    };
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            if (inner(float(x), float(y)) && inner(float(x + 1), float(y)) && inner(float(x), float(y + 1)) &&
                inner(float(x + 1), float(y + 1)))
                v.push_back(size_t(y) * size_t(size) + size_t(x));
    return v;
}

TEST(PathTracer, WhiteFurnaceAlbedoOneRendersOne) {
    // Albedo 1 inside radiance 1: every pixel 1. Bound: the image mean within 4 SE of 1, each pixel
    // within 6 of its own SE (or 1e-3 where a pixel's samples agree).
    const Furnace f(lambert(Vec3{1.0f}));
    const TraceResult r = f.render(64 / kWorkScale);
    const Estimate e = image_estimate(r, inner_pixels(f, 16));
    EXPECT_GT(inner_pixels(f, 16).size(), 30u);
    EXPECT_NEAR(e.mean, 1.0, 4.0 * e.se + 1e-4) << "SE " << e.se;
    for (size_t i = 0; i < r.radiance.size(); ++i)
        EXPECT_NEAR(luminance(r.radiance[i]), 1.0, 6.0 * std::sqrt(r.lum_variance[i] / r.spp) + 1e-3) << "pixel " << i;
}

TEST(PathTracer, FurnaceAlbedoHalfRendersHalf) {
    // A convex albedo-0.5 sphere sees only the emitter: 0.5 * 1 on the sphere, 1 around it.
    const Furnace f(lambert(Vec3{0.5f}));
    const TraceResult r = f.render(64 / kWorkScale);
    const Estimate e = image_estimate(r, inner_pixels(f, 16));
    EXPECT_NEAR(e.mean, 0.5, 4.0 * e.se + 1e-4) << "SE " << e.se;
    EXPECT_LT(e.se, 0.01);
}

TEST(PathTracer, ClosedEmissiveSphereSumsTheGeometricSeries) {
    // Inside a closed sphere that emits 1 and reflects half: L = 1 + 0.5 L, so L = 2 everywhere.
    // Every bounce and Russian roulette matter here. Bound: image mean within 4 SE of 2.
    Scene scene;
    scene.add_shape(Sphere{{0, 0, 0}, 1.0f});
    SurfaceMaterial m = lambert(Vec3{0.5f}, Vec3{1.0f});
    m.two_sided = true;
    RenderScene rs;
    rs.scene = &scene;
    rs.materials = {m};
    rs.prim_material = {0};
    const auto accel = build_accel("brute", scene);
    TraceOptions o;
    o.width = o.height = 8;
    o.spp = 128 / kWorkScale;
    o.seed = 7;
    o.progress = false;
    o.variance = true;
    for (LightStrategy s : {LightStrategy::Mis, LightStrategy::LightOnly, LightStrategy::BsdfOnly}) {
        o.strategy = s;
        const TraceResult r = trace_path(rs, *accel, Camera({0.1f, 0.2f, 0.3f}, {0, 0, -1}), o);
        const Estimate e = image_estimate(r, all_pixels(r));
        EXPECT_NEAR(e.mean, 2.0, 4.0 * e.se + 1e-4) << "strategy " << int(s) << " SE " << e.se;
        EXPECT_LT(e.se, 0.05);
    }
}

TEST(PathTracer, GlassSphereInFurnaceStaysAtOne) {
    // A lossless dielectric neither creates nor absorbs light: a glass sphere in the furnace
    // disappears. Bound: the sphere's mean within 4 SE of 1 and below 1.02 in absolute terms.
    const Furnace f(dielectric(1.5f));
    const TraceResult r = f.render(64 / kWorkScale);
    const Estimate e = image_estimate(r, inner_pixels(f, 16));
    EXPECT_NEAR(e.mean, 1.0, 4.0 * e.se + 1e-4) << "SE " << e.se;
    EXPECT_NEAR(e.mean, 1.0, 0.02);
}

TEST(Dielectric, ReflectanceAndTransmittanceSumToOneAtEveryAngle) {
    for (const float eta : {1.5f, 1.0f / 1.5f, 2.4f, 1.0f / 2.4f, 1.0f}) {
        const float critical_cos = eta < 1.0f ? std::sqrt(1.0f - eta * eta) : 0.0f;
        for (int i = 0; i <= 1000; ++i) {
            const float cos_i = float(i) / 1000.0f;
            const float R = fresnel_dielectric(cos_i, eta), T = fresnel_transmittance(cos_i, eta);
            ASSERT_GE(R, 0.0f);
            ASSERT_LE(R, 1.0f);
            ASSERT_GE(T, 0.0f);
            if (cos_i > 0.0f) {
                ASSERT_NEAR(R + T, 1.0f, 2e-5f) << "eta " << eta << " cos " << cos_i;
            }
            if (cos_i < critical_cos - 1e-6f) {  // beyond the critical angle: total internal reflection
                ASSERT_EQ(R, 1.0f) << "eta " << eta << " cos " << cos_i;
                ASSERT_EQ(T, 0.0f);
            }
        }
    }
    EXPECT_NEAR(fresnel_dielectric(1.0f, 1.5f), 0.04f, 1e-6f);  // ((1.5 - 1) / (1.5 + 1))^2
    EXPECT_NEAR(fresnel_dielectric(0.0f, 1.5f), 1.0f, 1e-6f);   // grazing: everything reflects
}

TEST(Dielectric, SampledDirectionsObeySnellAndCarryTheFresnelShares) {
    const SurfaceMaterial glass = dielectric(1.5f);
    const Vec3 n{0, 0, 1};
    Rng rng(3, 5);
    for (float cos_o : {0.9f, 0.5f, 0.1f, -0.9f, -0.5f, -0.2f}) {
        const Vec3 wo{std::sqrt(1.0f - cos_o * cos_o), 0.0f, cos_o};
        const float eta = cos_o > 0.0f ? 1.5f : 1.0f / 1.5f;
        int reflected = 0;
        constexpr int kN = 4000;
        for (int i = 0; i < kN; ++i) {
            BsdfSample s;
            ASSERT_TRUE(sample_bsdf(glass, n, wo, rng.uniform(), rng.uniform(), rng.uniform(), s));
            ASSERT_TRUE(s.delta);
            ASSERT_NEAR(length(s.wi), 1.0f, 1e-5f);
            if (s.wi.z * cos_o > 0.0f) {
                ++reflected;
                ASSERT_NEAR(s.wi.x, -wo.x, 1e-5f);
            } else {
                // Snell: sin_t = sin_i / eta, in the plane of incidence on the far side.
                ASSERT_NEAR(-s.wi.x, wo.x / eta, 1e-5f);
                ASSERT_NEAR(s.weight.x, 1.0f / (eta * eta), 1e-6f);
            }
        }
        const double R = fresnel_dielectric(std::fabs(cos_o), eta);
        const double se = std::sqrt(R * (1 - R) / kN);
        EXPECT_NEAR(double(reflected) / kN, R, 4 * se + 1e-9) << "cos_o " << cos_o;
    }
}

TEST(Bsdf, GlossyAndLambertAreEnergyBounded) {
    // The directional albedo E[weight] of every material is at most 1 (4 SE margin), and sampling
    // agrees with eval/pdf: weight == eval / pdf for each sample.
    Rng rng(11, 13);
    const Vec3 n{0, 0, 1};
    const SurfaceMaterial mats[] = {lambert(Vec3{1.0f}), glossy(Vec3{0.0f}, Vec3{1.0f}, 1.0f),
                                    glossy(Vec3{0.0f}, Vec3{1.0f}, 20.0f), glossy(Vec3{0.0f}, Vec3{1.0f}, 500.0f),
                                    glossy(Vec3{0.7f}, Vec3{0.7f}, 30.0f)};
    for (const SurfaceMaterial& m : mats)
        for (float cos_o : {1.0f, 0.7f, 0.3f, 0.05f}) {
            const Vec3 wo{std::sqrt(1.0f - cos_o * cos_o), 0.0f, cos_o};
            constexpr int kN = 20000;
            double sum = 0, sum2 = 0;
            for (int i = 0; i < kN; ++i) {
                BsdfSample s;
                if (!sample_bsdf(m, n, wo, rng.uniform(), rng.uniform(), rng.uniform(), s)) continue;
                const Vec3 expect = eval_bsdf(m, n, wo, s.wi) / pdf_bsdf(m, n, wo, s.wi);
                ASSERT_NEAR(s.weight.y, expect.y, 1e-4f * std::max(1.0f, expect.y));
                sum += s.weight.y;
                sum2 += double(s.weight.y) * s.weight.y;
            }
            const double mean = sum / kN, se = std::sqrt(std::max(0.0, sum2 / kN - mean * mean) / kN);
            EXPECT_LE(mean, 1.0 + 4 * se + 1e-6) << "exponent " << m.exponent << " cos_o " << cos_o;
            if (m.kind == SurfaceKind::Lambert) {
                EXPECT_NEAR(mean, 1.0, 1e-5);
            }
        }
    // Too much asked for: scaled down so that albedo + specular <= 1 per channel.
    const SurfaceMaterial g = glossy(Vec3{0.9f}, Vec3{0.6f}, 10.0f);
    EXPECT_LE(g.albedo.x + g.specular.x, 1.0f + 1e-6f);
}

/// The Cornell box with `strategy`, w x h pixels; `glossy_tall_box`: the tall box a sharp glossy
/// reflector (albedo 0.2, Phong lobe 0.7 with exponent 1000) that mirrors the light.
TraceResult render_cornell(const Scene& scene, const Accel& accel, int w, int h, uint32_t spp, LightStrategy strategy,
                           unsigned threads, uint64_t seed = 5, bool glossy_tall_box = false) {
    RenderScene rs = make_render_scene(scene);
    if (glossy_tall_box)
        for (size_t i = 0; i < scene.mesh.materials.size(); ++i)
            if (scene.mesh.materials[i].name == "tallBox") rs.materials[1 + i] = glossy(Vec3{0.2f}, Vec3{0.7f}, 1000.0f);
    TraceOptions o;
    o.width = w;
    o.height = h;
    o.spp = spp;
    o.seed = seed;
    o.threads = threads;
    o.strategy = strategy;
    o.progress = false;
    o.variance = true;
    return trace_path(rs, accel, *rs.camera, o);
}

TEST(PathTracer, LightBsdfAndMisAgreeOnTheCornellBox) {
    // Independent seeds per strategy. 16 regions of 8x8 pixels; each region's mean luminance under
    // every pair of strategies agrees within 3 combined SE.
    const Scene scene = load_scene("cornell");
    const auto accel = build_accel("bvh8", scene);
    const uint32_t spp = 96 / kWorkScale;
    const LightStrategy strategies[3] = {LightStrategy::Mis, LightStrategy::LightOnly, LightStrategy::BsdfOnly};
    TraceResult r[3];
    for (int s = 0; s < 3; ++s) r[s] = render_cornell(scene, *accel, 32, 32, spp, strategies[s], 0, 100 + s);
    for (int ry = 0; ry < 4; ++ry)
        for (int rx = 0; rx < 4; ++rx) {
            std::vector<size_t> region;
            for (int y = 8 * ry; y < 8 * ry + 8; ++y)
                for (int x = 8 * rx; x < 8 * rx + 8; ++x) region.push_back(size_t(y) * 32 + size_t(x));
            Estimate e[3];
            for (int s = 0; s < 3; ++s) e[s] = image_estimate(r[s], region);
            for (int a = 0; a < 3; ++a)
                for (int b = a + 1; b < 3; ++b)
                    EXPECT_NEAR(e[a].mean, e[b].mean, 3.0 * std::hypot(e[a].se, e[b].se))
                        << "region " << rx << "," << ry << " strategies " << a << " vs " << b;
        }
}

TEST(PathTracer, MisIsTheLeastNoisyStrategy) {
    // On the all-diffuse box MIS and light sampling alone are within a percent of each other (the
    // BSDF's density is far below the light's almost everywhere), so the comparison uses the box
    // with a sharp glossy tall box, where each strategy alone fails somewhere: light sampling on the
    // highlight, BSDF sampling on the diffuse walls. MIS and light-only share their seed (the same
    // paths, only the weights differ), so their difference is not noise. Bound: MIS's total
    // per-sample variance below 0.9 times either other strategy's.
    const Scene scene = load_scene("cornell");
    const auto accel = build_accel("bvh8", scene);
    const uint32_t spp = 64 / kWorkScale;
    double total_var[3] = {};
    const LightStrategy strategies[3] = {LightStrategy::Mis, LightStrategy::LightOnly, LightStrategy::BsdfOnly};
    for (int s = 0; s < 3; ++s) {
        const TraceResult r = render_cornell(scene, *accel, 32, 32, spp, strategies[s], 0, 9, true);
        for (float v : r.lum_variance) total_var[s] += v;
    }
    EXPECT_LT(total_var[0], 0.9 * total_var[1]) << "MIS vs light sampling only";
    EXPECT_LT(total_var[0], 0.9 * total_var[2]) << "MIS vs BSDF sampling only";
}

TEST(PathTracer, ImageIsBitIdenticalWhateverTheThreadCount) {
    const Scene scene = load_scene("cornell");
    const auto accel = build_accel("bvh8", scene);
    // 40x24: tiles cut at the edges; 5 samples: waves of several samples per path batch.
    const TraceResult one = render_cornell(scene, *accel, 40, 24, 5, LightStrategy::Mis, 1);
    for (unsigned threads : {2u, 7u}) {
        const TraceResult other = render_cornell(scene, *accel, 40, 24, 5, LightStrategy::Mis, threads);
        ASSERT_EQ(one.sum.size(), other.sum.size());
        for (size_t i = 0; i < one.sum.size(); ++i)
            ASSERT_EQ(std::bit_cast<uint64_t>(one.sum[i]), std::bit_cast<uint64_t>(other.sum[i]))
                << threads << " threads, value " << i;
    }
    // A different seed gives a different image.
    const TraceResult reseeded = render_cornell(scene, *accel, 40, 24, 5, LightStrategy::Mis, 1, 6);
    EXPECT_NE(one.sum, reseeded.sum);
    // Whitted too.
    const RenderScene rs = make_render_scene(scene);
    TraceOptions o;
    o.width = 40;
    o.height = 24;
    o.spp = 2;
    o.progress = false;
    o.threads = 1;
    const TraceResult w1 = trace_whitted(rs, *accel, *rs.camera, o);
    o.threads = 7;
    const TraceResult w7 = trace_whitted(rs, *accel, *rs.camera, o);
    EXPECT_EQ(w1.sum, w7.sum);
}

// The committed reference: the Cornell box at 32x32 with the standard camera, MIS, 16384 spp
// (seed 1), as 32 * 32 * 3 floats in text. Regenerate with
//   thicket_unit_tests --gtest_also_run_disabled_tests --gtest_filter='*DISABLED_WriteCornellReference*'
const std::string kReferencePath = std::string(THICKET_TEST_DATA) + "/cornell_32x32_reference.txt";

TEST(PathTracer, DISABLED_WriteCornellReference) {
    const Scene scene = load_scene("cornell");
    const auto accel = build_accel("bvh8", scene);
    const TraceResult r = render_cornell(scene, *accel, 32, 32, 16384, LightStrategy::Mis, 0, 1);
    std::ofstream out(kReferencePath);
    out.precision(9);
    for (const Vec3& c : r.radiance) out << c.x << ' ' << c.y << ' ' << c.z << '\n';
    ASSERT_TRUE(out.good());
}

TEST(PathTracer, CornellBoxMatchesTheConvergedReference) {
    // Bound: the RMSE (over pixels and channels) against the reference is within 1.3 times the RMSE
    // that noise alone explains (from the samples' own variance), and below 0.12 in absolute terms at
    // 64 spp (most of it from the pixels on the light's edge, luminance 0 or 12.6; the bound scales
    // with 1/sqrt(spp) in sanitizer builds). A bias of a few percent in any large region would exceed it.
    std::ifstream in(kReferencePath);
    ASSERT_TRUE(in.good()) << "missing " << kReferencePath;
    std::vector<Vec3> ref(32 * 32);
    for (Vec3& c : ref) in >> c.x >> c.y >> c.z;
    ASSERT_TRUE(bool(in)) << "short reference file " << kReferencePath;
    const Scene scene = load_scene("cornell");
    const auto accel = build_accel("bvh8", scene);
    const TraceResult r = render_cornell(scene, *accel, 32, 32, 64 / kWorkScale, LightStrategy::Mis, 0, 77);
    double se2 = 0, lum_se2 = 0;
    for (size_t i = 0; i < ref.size(); ++i) {
        const float dl = luminance(r.radiance[i]) - luminance(ref[i]);
        se2 += double(dl) * dl;
        lum_se2 += double(r.lum_variance[i]) / r.spp;
    }
    const double rmse = std::sqrt(se2 / double(ref.size())), noise = std::sqrt(lum_se2 / double(ref.size()));
    EXPECT_LT(rmse, 1.3 * noise) << "luminance RMSE " << rmse << ", noise alone " << noise;
    EXPECT_LT(rmse, 0.12 * std::sqrt(double(kWorkScale)));
    // And the mean over the image (bias shows here without noise hiding it): within 4 SE.
    double mean_r = 0, mean_ref = 0;
    for (size_t i = 0; i < ref.size(); ++i) {
        mean_r += luminance(r.radiance[i]);
        mean_ref += luminance(ref[i]);
    }
    EXPECT_NEAR(mean_r / 1024.0, mean_ref / 1024.0, 4.0 * std::sqrt(lum_se2) / 1024.0);
}

}  // namespace
}  // namespace thicket::path_tracer_test
