// The bench: ray sets are reproducible to the byte and follow their documented rules, the
// agreement check catches wrong answers (alone and inside the measuring loop), and the JSON output
// parses with every required field.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bench/agreement.h"
#include "thicket/bench/primitive_probe.h"
#include "thicket/bench/bench_json.h"
#include "thicket/bench/bench_tables.h"
#include "thicket/bench/ray_sets.h"
#include "thicket/bench/rng.h"
#include "thicket/bench/runner.h"
#include "thicket/bench/timing.h"
#include "thicket/core/error.h"
#include "thicket/util/npy.h"

namespace bench_test {

namespace fs = std::filesystem;
using namespace thicket;

namespace {

const std::vector<std::string> kAllSets{"primary", "shadow", "diffuse", "random"};

const Scene& cornell() {
    static const Scene scene = load_scene("cornell");
    return scene;
}

std::vector<RaySet> standard_sets(const Scene& scene, int width, int height, unsigned threads) {
    const auto accel = build_accel(kRaySetHitSpec, scene);
    RaySetOptions options;
    options.width = width;
    options.height = height;
    return generate_ray_sets(scene, *accel, kAllSets, options, threads);
}

std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// FNV-1a over the bytes of a ray set in the `thicket trace` layout.
uint64_t fnv1a(const std::vector<float>& values) {
    uint64_t h = 1469598103934665603ULL;
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    for (size_t i = 0; i < values.size() * sizeof(float); ++i) h = (h ^ bytes[i]) * 1099511628211ULL;
    return h;
}

class TempDir {
public:
    TempDir() {
        path_ = fs::temp_directory_path() / ("thicket_bench_test_" + std::to_string(getpid()) + "_" +
                                             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() { fs::remove_all(path_); }
    fs::path operator/(const std::string& name) const { return path_ / name; }

private:
    fs::path path_;
};

// ---- ray sets ----------------------------------------------------------------------------------

TEST(BenchRaySets, FixedSeedsReproduceByteIdenticalFiles) {
    std::vector<const Scene*> scenes{&cornell()};
    const std::string shared = thicket::testing::shared_scene_dir();
    const std::string teapot = shared.empty() ? "" : shared + "/teapot.ply";
    if (!teapot.empty() && fs::exists(teapot)) scenes.push_back(&thicket::testing::cached_scene(teapot));
    TempDir dir;
    for (const Scene* scene : scenes) {
        SCOPED_TRACE(scene->name);
        // Different thread counts too: threads only speed up tracing, never change a ray.
        const std::vector<RaySet> a = standard_sets(*scene, 48, 32, 1);
        const std::vector<RaySet> b = standard_sets(*scene, 48, 32, 0);
        ASSERT_EQ(a.size(), kAllSets.size());
        for (size_t s = 0; s < a.size(); ++s) {
            SCOPED_TRACE(a[s].name);
            EXPECT_FALSE(a[s].rays.empty());
            const std::vector<float> ma = ray_matrix(a[s].rays), mb = ray_matrix(b[s].rays);
            ASSERT_EQ(ma.size(), mb.size());
            EXPECT_EQ(std::memcmp(ma.data(), mb.data(), ma.size() * sizeof(float)), 0);
            const fs::path fa = dir / (a[s].name + "_a.npy"), fb = dir / (a[s].name + "_b.npy");
            write_npy_f32(fa.string(), {a[s].rays.size(), 8}, ma);
            write_npy_f32(fb.string(), {b[s].rays.size(), 8}, mb);
            const std::string bytes_a = read_all(fa);
            EXPECT_EQ(bytes_a, read_all(fb));
            EXPECT_EQ(bytes_a.size(), 128 + ma.size() * sizeof(float));  // header padded to 64-byte multiple
            // The file reads back as the very rays, in the `thicket trace` layout.
            const NpyFloatArray back = read_npy_matrix(fa.string(), 8);
            ASSERT_EQ(back.values.size(), ma.size());
            EXPECT_EQ(std::memcmp(back.values.data(), ma.data(), ma.size() * sizeof(float)), 0);
        }
    }
}

#if !defined(__FMA__)
// The random set uses only correctly rounded arithmetic, so its bytes are fixed for all time on any
// IEEE machine (builds that may contract a*b+c into an FMA, such as -march=native, are excluded).
TEST(BenchRaySets, RandomSetBytesAreFixed) {
    RaySetOptions options;
    options.width = 16;
    options.height = 16;
    const auto accel = build_accel(kRaySetHitSpec, cornell());
    const std::vector<std::string> names{"random"};
    const RaySet set = generate_ray_sets(cornell(), *accel, names, options, 1).front();
    ASSERT_EQ(set.rays.size(), 256u);
    EXPECT_EQ(fnv1a(ray_matrix(set.rays)), 0x501c81c02493d2c3ULL) << std::hex << fnv1a(ray_matrix(set.rays));
}
#endif

TEST(BenchRaySets, PrimaryRaysStartAtTheCameraInPixelOrder) {
    const std::vector<RaySet> sets = standard_sets(cornell(), 40, 30, 0);
    const RaySet& primary = sets[0];
    EXPECT_EQ(primary.name, "primary");
    EXPECT_FALSE(primary.any_hit);
    ASSERT_EQ(primary.rays.size(), 40u * 30u);
    const auto accel = build_accel(kRaySetHitSpec, cornell());
    RaySetOptions options;
    options.width = 40;
    options.height = 30;
    const RaySetView view = ray_set_view(cornell(), *accel, options);
    EXPECT_FALSE(view.interior);  // the box is open towards +z: the probe from its centre sees out
    const Camera camera = view.camera;
    EXPECT_EQ(camera.position(), auto_camera(cornell().bounds(), 40.0f / 30.0f).position());
    for (size_t k = 0; k < primary.rays.size(); ++k) {
        const Ray& r = primary.rays[k];
        ASSERT_EQ(r.org, camera.position());
        ASSERT_EQ(r.tmin, 0.0f);
        ASSERT_EQ(r.tmax, kInfinity);
        const Ray expected = camera.generate(float(k % 40) + 0.5f, float(k / 40) + 0.5f, 40, 30);
        ASSERT_EQ(r.dir, expected.dir) << "ray " << k;
    }
}

TEST(BenchRaySets, GivenCameraIsUsed) {
    const auto accel = build_accel(kRaySetHitSpec, cornell());
    RaySetOptions options;
    options.width = 8;
    options.height = 8;
    options.camera = parse_camera("0,1,3,0,1,0,60");
    const std::vector<std::string> names{"primary"};
    const RaySet set = generate_ray_sets(cornell(), *accel, names, options).front();
    for (const Ray& r : set.rays) EXPECT_EQ(r.org, (Vec3{0, 1, 3}));
}

// Recomputes the primary hit a shadow or diffuse ray starts from: point and faced unit normal.
struct PrimaryHit {
    Vec3 point, normal;
};
PrimaryHit primary_hit(const Scene& scene, const Accel& accel, const Ray& primary) {
    const Hit h = accel.intersect(primary);
    EXPECT_TRUE(h.found());
    Vec3 n = normalize(scene.geometric_normal(h.prim));
    if (dot(n, primary.dir) > 0) n = -n;
    return {primary.org + primary.dir * h.t, n};
}

TEST(BenchRaySets, ShadowRaysAreAnyHitAndEndJustBeforeTheLight) {
    const Scene& scene = cornell();
    const auto accel = build_accel(kRaySetHitSpec, scene);
    const std::vector<RaySet> sets = standard_sets(scene, 40, 30, 0);
    const RaySet& primary = sets[0];
    const RaySet& shadow = sets[1];
    EXPECT_EQ(shadow.name, "shadow");
    EXPECT_TRUE(shadow.any_hit);
    ASSERT_FALSE(shadow.rays.empty());
    ASSERT_EQ(shadow.source.size(), shadow.rays.size());

    RaySetOptions options;
    options.width = 40;
    options.height = 30;
    const Vec3 light = ray_set_view(scene, *accel, options).light;
    EXPECT_EQ(light, light_above_bounds(scene.bounds()));
    EXPECT_GT(light.y, scene.bounds().max.y);  // open space above the scene
    const float offset = surface_offset(scene.bounds());
    for (size_t i = 0; i < shadow.rays.size(); ++i) {
        const Ray& r = shadow.rays[i];
        ASSERT_LT(shadow.source[i], primary.rays.size());
        if (i) {
            ASSERT_GT(shadow.source[i], shadow.source[i - 1]);  // pixel order
        }
        const PrimaryHit p = primary_hit(scene, *accel, primary.rays[shadow.source[i]]);
        EXPECT_LT(length(r.org - (p.point + p.normal * offset)), 1e-5f);
        EXPECT_GT(dot(p.normal, light - p.point), 0.0f);  // the surface faces the light
        EXPECT_NEAR(length(r.dir), 1.0f, 1e-5f);
        const float to_light = length(light - r.org);
        EXPECT_LT(r.tmax, to_light);                // ends before the light...
        EXPECT_GT(r.tmax, to_light * (1 - 1e-3f));  // ...but just before it
        EXPECT_LT(length(r.org + r.dir * to_light - light), 1e-4f * to_light);  // aimed at the light
        EXPECT_EQ(r.tmin, 0.0f);
    }
}

TEST(BenchRaySets, DiffuseDirectionsLieInTheHemisphereOfTheHitNormal) {
    const Scene& scene = cornell();
    const auto accel = build_accel(kRaySetHitSpec, scene);
    const std::vector<RaySet> sets = standard_sets(scene, 64, 48, 0);
    const RaySet& primary = sets[0];
    const RaySet& diffuse = sets[2];
    EXPECT_FALSE(diffuse.any_hit);
    ASSERT_EQ(diffuse.source.size(), diffuse.rays.size());
    size_t primary_hits = 0;
    for (const Ray& r : primary.rays) primary_hits += accel->intersect(r).found();
    EXPECT_EQ(diffuse.rays.size(), primary_hits);  // one per primary hit (no degenerate triangles here)

    double cos_sum = 0.0;
    for (size_t i = 0; i < diffuse.rays.size(); ++i) {
        const Ray& r = diffuse.rays[i];
        const PrimaryHit p = primary_hit(scene, *accel, primary.rays[diffuse.source[i]]);
        const float c = dot(r.dir, p.normal);
        ASSERT_GT(c, 0.0f) << "ray " << i;
        EXPECT_NEAR(length(r.dir), 1.0f, 1e-5f);
        EXPECT_EQ(r.tmax, kInfinity);
        cos_sum += c;
    }
    // Cosine-weighted: E[cos] = 2/3 (uniform would give 1/2).
    EXPECT_NEAR(cos_sum / double(diffuse.rays.size()), 2.0 / 3.0, 0.02);
}

TEST(BenchRaySets, RandomRaysStartInsideTheBoundsWithUniformDirections) {
    const std::vector<RaySet> sets = standard_sets(cornell(), 64, 48, 0);
    const RaySet& random = sets[3];
    ASSERT_EQ(random.rays.size(), 64u * 48u);
    Vec3 mean{0.0f};
    for (const Ray& r : random.rays) {
        EXPECT_TRUE(cornell().bounds().contains(r.org));
        EXPECT_NEAR(length(r.dir), 1.0f, 1e-5f);
        mean += r.dir;
    }
    EXPECT_LT(length(mean / float(random.rays.size())), 0.05f);
}

// A closed box room, 4 x 2 x 3, its faces wound to face inwards (a room) or outwards (an object).
Scene box_scene(bool facing_inwards) {
    Scene s;
    s.name = facing_inwards ? "room" : "block";
    const Vec3 lo{-2, 0, -1.5f}, hi{2, 2, 1.5f};
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            Vec3 q[4];
            for (int k = 0; k < 4; ++k) {
                q[k][axis] = side ? hi[axis] : lo[axis];
                q[k][u] = (k == 1 || k == 2) ? hi[u] : lo[u];
                q[k][v] = (k >= 2) ? hi[v] : lo[v];
            }
            Vec3 outward{0.0f};
            outward[axis] = side ? 1.0f : -1.0f;
            const bool flip = (dot(cross(q[1] - q[0], q[2] - q[0]), outward) > 0) == facing_inwards;
            const uint32_t base = uint32_t(s.mesh.positions.size());
            s.mesh.positions.insert(s.mesh.positions.end(), q, q + 4);
            for (uint32_t t : {0u, 1u, 2u, 0u, 2u, 3u})
                s.mesh.indices.push_back(base + (flip && t != 0 ? (t == 1 ? 3u : t == 3 ? 1u : 2u) : t));
        }
    }
    return s;
}

TEST(BenchRaySets, InteriorScenesAreSeenFromInsideWithTheLightUnderTheCeiling) {
    RaySetOptions options;
    options.width = 32;
    options.height = 24;
    const Scene room = box_scene(true);
    const auto room_accel = build_accel(kRaySetHitSpec, room);
    const RaySetView inside = ray_set_view(room, *room_accel, options);
    EXPECT_TRUE(inside.interior);
    EXPECT_EQ(inside.camera.position(), room.bounds().center());
    EXPECT_EQ(inside.light, (Vec3{0, 1.75f, 0}));  // three quarters of the way up to the ceiling at y = 2
    const std::vector<RaySet> sets = generate_ray_sets(room, *room_accel, inside, kAllSets, options);
    EXPECT_EQ(sets[0].rays.size(), 32u * 24u);
    for (const Ray& r : sets[1].rays) {  // nothing stands between the walls and the light
        EXPECT_FALSE(room_accel->occluded(r));
        EXPECT_GT(dot(r.dir, inside.light - r.org), 0.0f);
    }
    EXPECT_FALSE(sets[1].rays.empty());

    // The same box as a closed object: its centre is inside it, so it is framed from outside.
    const Scene block = box_scene(false);
    const auto block_accel = build_accel(kRaySetHitSpec, block);
    const RaySetView outside = ray_set_view(block, *block_accel, options);
    EXPECT_FALSE(outside.interior);
    EXPECT_EQ(outside.camera.position(), auto_camera(block.bounds(), 32.0f / 24.0f).position());
    EXPECT_EQ(outside.light, light_above_bounds(block.bounds()));

    // A given camera is kept either way; the light still follows the scene.
    options.camera = parse_camera("1,1,1,0,1,0");
    const RaySetView given = ray_set_view(room, *room_accel, options);
    EXPECT_EQ(given.camera.position(), (Vec3{1, 1, 1}));
    EXPECT_EQ(given.light, inside.light);
}

TEST(BenchRaySets, BadNamesAndSizesAreRejected) {
    EXPECT_EQ(parse_ray_set_list("shadow, primary,shadow"), (std::vector<std::string>{"shadow", "primary"}));
    EXPECT_THROW(parse_ray_set_list("primary,ambient"), Error);
    EXPECT_THROW(parse_ray_set_list(""), Error);
    RaySetOptions o;
    parse_ray_set_size("640x480", o);
    EXPECT_EQ(o.width, 640);
    EXPECT_EQ(o.height, 480);
    EXPECT_THROW(parse_ray_set_size("640", o), Error);
    EXPECT_THROW(parse_ray_set_size("0x10", o), Error);
    EXPECT_THROW(parse_ray_set_size("10x-1", o), Error);
}

TEST(BenchRaySets, SamplersStayInTheirDomains) {
    Pcg32 rng(7);
    for (int i = 0; i < 10000; ++i) {
        const float f = rng.next_float();
        ASSERT_TRUE(f >= 0.0f && f < 1.0f);
        const Vec3 n = sample_unit_sphere(rng);
        ASSERT_NEAR(length(n), 1.0f, 1e-6f);
        ASSERT_GT(dot(sample_cosine_hemisphere(rng, n), n), 0.0f);
    }
    // Grazing normals along the axes, where the basis construction is most delicate.
    for (Vec3 n : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, Vec3{1, 0, 0}, Vec3{0, -1, 0}})
        for (int i = 0; i < 1000; ++i) ASSERT_GT(dot(sample_cosine_hemisphere(rng, n), n), 0.0f);
}

// ---- agreement ---------------------------------------------------------------------------------

TEST(BenchAgreement, DeliberatelyWrongAnswersAreFlagged) {
    const Scene& scene = cornell();
    const auto accel = build_accel("bvh", scene);
    const RaySet primary = standard_sets(scene, 32, 24, 0)[0];
    std::vector<Hit> reference(primary.rays.size());
    for (size_t i = 0; i < reference.size(); ++i) reference[i] = accel->intersect(primary.rays[i]);
    std::vector<size_t> hit_rays;
    for (size_t i = 0; i < reference.size(); ++i)
        if (reference[i].found()) hit_rays.push_back(i);
    ASSERT_GE(hit_rays.size(), 3u);

    std::vector<Hit> candidate = reference;
    Agreement a = compare_hits(reference, candidate);
    EXPECT_EQ(a.percent(), 100.0);
    EXPECT_EQ(a.max_dt, 0.0);

    // Another primitive, farther away: wrong.
    const size_t wrong_prim = hit_rays[0];
    candidate[wrong_prim].prim = (candidate[wrong_prim].prim + 1) % uint32_t(scene.primitive_count());
    candidate[wrong_prim].t *= 1.5f;
    // The right primitive a little farther (rounding of another triangle test): not a
    // disagreement, but the t difference shows it.
    const size_t wrong_t = hit_rays[1];
    candidate[wrong_t].t *= 1.0005f;
    a = compare_hits(reference, candidate);
    EXPECT_EQ(a.disagreeing(), 1u);
    EXPECT_EQ(a.first_mismatch, wrong_prim);
    EXPECT_LT(a.percent(), 100.0);
    EXPECT_NEAR(a.max_dt_rel, 0.0005 / 1.0005, 1e-6);  // the disagreeing ray does not count here
    candidate[wrong_prim] = reference[wrong_prim];
    a = compare_hits(reference, candidate);
    EXPECT_EQ(a.disagreeing(), 0u);
    EXPECT_GT(a.max_dt, 0.0);
    // The right primitive 1% away is a wrong answer, not rounding.
    candidate[wrong_t].t = reference[wrong_t].t * 1.01f;
    EXPECT_EQ(compare_hits(reference, candidate).first_mismatch, wrong_t);
    candidate[wrong_t] = reference[wrong_t];

    // A hit reported as a miss.
    candidate[hit_rays[2]] = Hit{};
    EXPECT_EQ(compare_hits(reference, candidate).first_mismatch, hit_rays[2]);
    candidate[hit_rays[2]] = reference[hit_rays[2]];

    // Another primitive at the very same t (what a structure with permuted leaf ids reports): the
    // distance alone would pass it; probing the named primitive flags it.
    const PrimitiveProbe probe(scene, "moller");
    const TieCheck tie_is_real = [&](size_t i, const Hit& h) {
        return identical_hits(probe.hit(h.prim, primary.rays[i]), h);
    };
    EXPECT_EQ(compare_hits(reference, candidate, {}, tie_is_real).disagreeing(), 0u);
    candidate[hit_rays[0]].prim = (reference[hit_rays[0]].prim + 1) % uint32_t(scene.primitive_count());
    EXPECT_EQ(compare_hits(reference, candidate).disagreeing(), 0u) << "the distance-only rule cannot see it";
    EXPECT_EQ(compare_hits(reference, candidate, {}, tie_is_real).first_mismatch, hit_rays[0]);

    // A tie: another primitive at the same distance (shared edge) is right.
    const Hit ref{2.0f, 0.1f, 0.2f, 5};
    EXPECT_TRUE(hits_agree(ref, Hit{2.0f + 1e-5f, 0.5f, 0.5f, 6}));
    EXPECT_FALSE(hits_agree(ref, Hit{2.01f, 0.5f, 0.5f, 6}));
    EXPECT_TRUE(hits_agree(Hit{}, Hit{}));
    EXPECT_FALSE(hits_agree(ref, Hit{}));

    // Any-hit flags, and comparison against a sample of the reference's rays.
    const std::vector<uint8_t> flags{1, 0, 1, 1}, sampled{1, 1};
    const std::vector<uint32_t> index{0, 2};
    EXPECT_EQ(compare_occlusion(flags, sampled, index).percent(), 100.0);
    const std::vector<uint8_t> flipped{1, 1, 1, 1};
    EXPECT_EQ(compare_occlusion(flags, flipped).first_mismatch, 1u);
    EXPECT_THROW(compare_occlusion(flags, sampled), Error);
}

// A tracer that answers like a correct one except for one deliberately wrong ray per set.
class WrongTracer final : public Tracer {
public:
    WrongTracer() : inner_(make_accel_tracer("bvh")) {}
    std::string name() const override { return "wrong"; }
    bool parallel_build() const override { return false; }
    double build(const Scene& scene, unsigned threads) override { return inner_->build(scene, threads); }
    TracerFigures figures() const override { return inner_->figures(); }
    void trace(std::span<const Ray> rays, std::span<Hit> hits, unsigned threads, bool coherent) const override {
        inner_->trace(rays, hits, threads, coherent);
        for (Hit& h : hits) {
            if (h.found()) {
                h.prim ^= 1u;
                h.t *= 2.0f;
                break;
            }
        }
    }
    void occluded(std::span<const Ray> rays, std::span<uint8_t> out, unsigned threads) const override {
        inner_->occluded(rays, out, threads);
        if (!out.empty()) out[0] ^= 1u;
    }
    bool count(std::span<const Ray> rays, bool any_hit, RayCounters& total, unsigned threads) const override {
        return inner_->count(rays, any_hit, total, threads);
    }

private:
    std::unique_ptr<Tracer> inner_;
};

std::vector<BenchRow> small_bench(std::vector<TracerFactory> tracers) {
    const std::vector<RaySet> sets = standard_sets(cornell(), 32, 24, 0);
    BenchOptions options;
    options.reps = 2;
    options.threads = 2;
    return bench_scene(cornell(), "cornell \"box\"\\\n", tracers, sets, options);
}

TEST(BenchRunner, WrongTracerIsFlaggedRayForRay) {
    // A correct structure stands in for Embree-high as the reference.
    TracerFactory reference = accel_tracer_factory("brute");
    reference.name = kReferenceTracer;
    const TracerFactory wrong{"wrong", [] { return std::make_unique<WrongTracer>(); }};
    const std::vector<BenchRow> rows = small_bench({accel_tracer_factory("bvh"), reference, wrong});
    ASSERT_EQ(rows.size(), 3u * 4u * 2u);  // tracers x sets x thread counts
    EXPECT_EQ(rows.front().accel, kReferenceTracer);  // the reference runs first
    for (const BenchRow& r : rows) {
        SCOPED_TRACE(r.accel + " " + r.set + " " + std::to_string(r.threads));
        ASSERT_TRUE(r.agree.has_value());
        ASSERT_TRUE(r.ratio.has_value());
        EXPECT_GT(r.mrays, 0.0);
        EXPECT_LE(r.mrays_min, r.mrays);
        EXPECT_LE(r.mrays, r.mrays_max);
        EXPECT_EQ(r.stride, 1u);
        EXPECT_TRUE(r.nodes_per_ray.has_value());
        EXPECT_EQ(r.any_hit, r.set == "shadow");
        if (r.accel == "wrong") {
            EXPECT_EQ(r.disagreeing, 1u);
            EXPECT_LT(*r.agree, 100.0);
        } else {
            EXPECT_EQ(r.disagreeing, 0u);
            EXPECT_EQ(*r.agree, 100.0);
        }
        if (r.accel == kReferenceTracer) {
            EXPECT_EQ(*r.ratio, 1.0);
        }
    }
}

TEST(BenchRunner, SlowTracersAreTimedOnASample) {
    const std::vector<RaySet> sets = standard_sets(cornell(), 64, 48, 0);
    BenchOptions options;
    options.reps = 1;
    options.threads = 1;
    options.pass_budget_ms = 1e-6;  // everything is "slow"
    const std::vector<TracerFactory> tracers{accel_tracer_factory("brute")};
    const std::vector<BenchRow> rows = bench_scene(cornell(), "cornell", tracers, sets, options);
    ASSERT_EQ(rows.size(), 4u);
    for (const BenchRow& r : rows) {
        EXPECT_GT(r.stride, 1u);
        EXPECT_EQ(r.rays, (r.set_rays + r.stride - 1) / r.stride);
        EXPECT_FALSE(r.agree.has_value());  // no reference in this run
        EXPECT_FALSE(r.ratio.has_value());
    }
    EXPECT_NE(format_bench_tables(rows, TableStyle::Terminal).find(" 1/"), std::string::npos);
}

TEST(BenchRunner, DisturbedPassesAreRetriedAndMarked) {
    // The retry rule on scripted utilizations (no machine load needed): attempts judged at 0.5,
    // 0.7 and 0.6 of the CPU are all disturbed, so every row takes the 3 attempts allowed and
    // keeps the best, 0.7, and is marked.
    const std::vector<RaySet> sets = standard_sets(cornell(), 16, 16, 0);
    BenchOptions options;
    options.reps = 2;
    options.threads = 1;
    std::vector<int> attempts_seen;
    options.utilization = [&](int attempt, double measured) {
        EXPECT_GE(measured, 0.0);
        attempts_seen.push_back(attempt);
        const double scripted[3] = {0.5, 0.7, 0.6};
        return scripted[(attempt - 1) % 3];
    };
    const std::vector<TracerFactory> tracers{accel_tracer_factory("bvh")};
    std::vector<BenchRow> rows = bench_scene(cornell(), "cornell", tracers, sets, options);
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(attempts_seen.size(), 4u * 3u);
    for (const BenchRow& r : rows) {
        EXPECT_EQ(r.attempts, options.max_attempts);
        EXPECT_EQ(r.cpu_util, 0.7);
        EXPECT_TRUE(r.nodes_per_ray.has_value());
    }
    EXPECT_NE(format_bench_tables(rows, TableStyle::Terminal).find(")!"), std::string::npos);
    EXPECT_NE(format_bench_noise(rows).find("4 rows timed again"), std::string::npos);
    EXPECT_NE(format_bench_noise(rows).find("4 still disturbed"), std::string::npos);

    // An attempt at 0.95 ends the retries: 2 attempts, the 0.95 kept, nothing marked.
    attempts_seen.clear();
    options.utilization = [&](int attempt, double) {
        attempts_seen.push_back(attempt);
        return attempt == 1 ? 0.5 : 0.95;
    };
    rows = bench_scene(cornell(), "cornell", tracers, sets, options);
    EXPECT_EQ(attempts_seen.size(), 4u * 2u);
    for (const BenchRow& r : rows) {
        EXPECT_EQ(r.attempts, 2);
        EXPECT_EQ(r.cpu_util, 0.95);
    }
    EXPECT_EQ(format_bench_tables(rows, TableStyle::Terminal).find(")!"), std::string::npos);
    EXPECT_NE(format_bench_noise(rows).find("0 still disturbed"), std::string::npos);

    // Undisturbed from the start: one attempt each.
    options.utilization = [](int, double) { return 1.0; };
    for (const BenchRow& r : bench_scene(cornell(), "cornell", tracers, sets, options)) EXPECT_EQ(r.attempts, 1);
}

TEST(BenchRunner, RoundsMergeIntoMediansWithTheRunToRunRange) {
    auto row = [](double mrays, double ratio, double build) {
        BenchRow r;
        r.scene = "s";
        r.accel = "bvh";
        r.set = "primary";
        r.mrays = mrays;
        r.mrays_min = mrays * 0.9;
        r.mrays_max = mrays * 1.1;
        r.ratio = ratio;
        r.build_ms = build;
        return r;
    };
    const std::vector<std::vector<BenchRow>> rounds{{row(1, 0.1, 10)}, {row(3, 0.3, 30)}, {row(2, 0.2, 20)}};
    const std::vector<BenchRow> merged = merge_bench_rounds(rounds);
    ASSERT_EQ(merged.size(), 1u);
    EXPECT_EQ(merged[0].rounds, 3);
    EXPECT_EQ(merged[0].mrays, 2.0);
    EXPECT_EQ(merged[0].mrays_min, 1.0);
    EXPECT_EQ(merged[0].mrays_max, 3.0);
    EXPECT_EQ(*merged[0].ratio, 0.2);
    EXPECT_EQ(merged[0].build_ms, 20.0);
    EXPECT_NE(format_bench_noise(merged).find("run-to-run"), std::string::npos);

    std::vector<std::vector<BenchRow>> mismatched = rounds;
    mismatched[1][0].set = "shadow";
    EXPECT_THROW(merge_bench_rounds(mismatched), Error);
    EXPECT_TRUE(merge_bench_rounds({}).empty());

    // A single round is not a merge: its slowest and fastest passes stay the range.
    const std::vector<std::vector<BenchRow>> one{{row(2, 0.2, 20)}};
    const std::vector<BenchRow> kept = merge_bench_rounds(one);
    EXPECT_EQ(kept[0].mrays_min, 1.8);
    EXPECT_EQ(kept[0].mrays_max, 2.2);
    EXPECT_EQ(kept[0].rounds, 1);
}

// ---- output ------------------------------------------------------------------------------------

TEST(BenchOutput, JsonParsesAndHasEveryField) {
    TracerFactory reference = accel_tracer_factory("brute");
    reference.name = kReferenceTracer;
    const std::vector<BenchRow> rows = small_bench({reference, accel_tracer_factory("bvh:builder=midpoint")});
    const nlohmann::json json = nlohmann::json::parse(bench_rows_json(rows));
    ASSERT_TRUE(json.is_array());
    ASSERT_EQ(json.size(), rows.size());
    for (const auto& row : json) {
        for (const char* field : kBenchJsonRequiredFields) EXPECT_TRUE(row.contains(field)) << field;
        EXPECT_EQ(row["scene"], "cornell \"box\"\\\n");  // escaped and restored exactly
        EXPECT_TRUE(row["accel"].is_string());
        EXPECT_TRUE(row["set"].is_string());
        EXPECT_TRUE(row["threads"].is_number_unsigned());
        EXPECT_TRUE(row["mrays"].is_number());
        EXPECT_TRUE(row["build_ms"].is_number());
        EXPECT_TRUE(row["bytes"].is_number_unsigned());
        EXPECT_TRUE(row["agree"].is_number());
        EXPECT_TRUE(row["cpu_util"].is_number());
        EXPECT_GE(row["attempts"].get<int>(), 1);
        EXPECT_GT(row["bytes"].get<double>(), 0.0);
    }
    EXPECT_EQ(json[0]["accel"], kReferenceTracer);

    // Without a reference, agreement is null but still present.
    const std::vector<BenchRow> alone = small_bench({accel_tracer_factory("bvh")});
    const nlohmann::json j2 = nlohmann::json::parse(bench_rows_json(alone));
    for (const auto& row : j2) {
        EXPECT_TRUE(row.contains("agree"));
        EXPECT_TRUE(row["agree"].is_null());
    }
    EXPECT_EQ(nlohmann::json::parse(bench_rows_json({})).size(), 0u);
}

TEST(BenchOutput, JsonQuoteEscapesEverythingJsonRequires) {
    const std::string nasty = std::string("a\"b\\c\n\t\x01\x1f/") + "\xc3\xa9";
    EXPECT_EQ(nlohmann::json::parse(json_quote(nasty)).get<std::string>(), nasty);
    EXPECT_EQ(json_quote("x\x01"), "\"x\\u0001\"");
}

TEST(BenchOutput, TablesShowEveryStructureAndSet) {
    TracerFactory reference = accel_tracer_factory("brute");
    reference.name = kReferenceTracer;
    const std::vector<BenchRow> rows = small_bench({reference, accel_tracer_factory("bvh")});
    const std::string text = format_bench_tables(rows, TableStyle::Terminal);
    const std::string md = format_bench_tables(rows, TableStyle::Markdown);
    for (const std::string& s : {std::string("embree-high"), std::string("bvh"), std::string("primary"),
                                 std::string("shadow"), std::string("diffuse"), std::string("random")}) {
        EXPECT_NE(text.find(s), std::string::npos) << s;
        EXPECT_NE(md.find(s), std::string::npos) << s;
    }
    EXPECT_NE(md.find("|---|"), std::string::npos);
    EXPECT_NE(text.find("single-threaded builder"), std::string::npos);
    EXPECT_NE(format_bench_noise(rows).find("median"), std::string::npos);
}

TEST(BenchTiming, MedianMinMax) {
    PassTimes t;
    EXPECT_EQ(t.median(), 0.0);
    t.seconds = {3, 1, 2};
    EXPECT_EQ(t.median(), 2.0);
    t.seconds = {4, 1, 3, 2};
    EXPECT_EQ(t.median(), 2.5);
    EXPECT_EQ(t.min(), 1.0);
    EXPECT_EQ(t.max(), 4.0);
    int calls = 0, after = 0;
    const PassTimes p = time_passes(5, [&] { ++calls; }, [&] { ++after; });
    EXPECT_EQ(calls, 6);  // one warm-up and five timed
    EXPECT_EQ(after, 6);
    EXPECT_EQ(p.seconds.size(), 5u);
    EXPECT_THROW(time_passes(0, [] {}), Error);
    EXPECT_EQ(mrays_per_second(2'000'000, 2.0), 1.0);
    PassTimes u;
    u.seconds = {1.0, 1.0};
    u.cpu_seconds = 3.0;
    EXPECT_EQ(u.total(), 2.0);
    EXPECT_EQ(u.cpu_utilization(2), 0.75);
}

}  // namespace

}  // namespace bench_test
