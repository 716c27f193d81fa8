// The Embree backend answers like Thicket's structures: the same barycentric convention, the same
// inclusive [tmin, tmax] interval, the same hits on a real scene, and it counts its memory.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <cmath>
#include <string>
#include <vector>

#include "embree_tracer.h"
#include "embree_tree.h"
#include "thicket/accel/registry.h"
#include "thicket/bench/agreement.h"
#include "thicket/bench/arbiter.h"
#include "thicket/bench/ray_sets.h"
#include "thicket/core/error.h"
#include "thicket/instances/instances.h"

using namespace thicket;

namespace {

Scene one_triangle() {
    Scene s;
    s.name = "one triangle";
    s.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    s.mesh.indices = {0, 1, 2};
    return s;
}

Ray down_at(float x, float y, float tmin = 0.0f, float tmax = kInfinity) {
    Ray r;
    r.org = {x, y, 1.0f};
    r.dir = {0, 0, -1};
    r.tmin = tmin;
    r.tmax = tmax;
    return r;
}

Hit trace_one(const Tracer& t, const Ray& r) {
    Hit h;
    t.trace(std::span<const Ray>(&r, 1), std::span<Hit>(&h, 1), 1, false);
    return h;
}

bool occluded_one(const Tracer& t, const Ray& r) {
    uint8_t f = 0;
    t.occluded(std::span<const Ray>(&r, 1), std::span<uint8_t>(&f, 1), 1);
    return f != 0;
}

/// The bench's four sets over `scene` at width x height pixels (the lecture BVH finds the hits
/// the secondary sets start from).
std::vector<RaySet> bench_sets(const Scene& scene, int width, int height) {
    const auto bvh = build_accel("bvh", scene);
    RaySetOptions options;
    options.width = width;
    options.height = height;
    const std::vector<std::string> names{"primary", "shadow", "diffuse", "random"};
    return generate_ray_sets(scene, *bvh, names, options, 1);
}

class EmbreeTracerTest : public ::testing::TestWithParam<EmbreeQuality> {};

TEST_P(EmbreeTracerTest, BarycentricsAreTheWeightsOfVertices1And2) {
    const Scene scene = one_triangle();
    auto embree = make_embree_tracer(GetParam());
    embree->build(scene, 1);
    const Hit h = trace_one(*embree, down_at(0.2f, 0.3f));
    ASSERT_TRUE(h.found());
    EXPECT_EQ(h.prim, 0u);
    EXPECT_NEAR(h.t, 1.0f, 1e-6f);
    EXPECT_NEAR(h.u, 0.2f, 1e-6f);
    EXPECT_NEAR(h.v, 0.3f, 1e-6f);

    auto brute = build_accel("brute", scene);
    const Hit b = brute->intersect(down_at(0.2f, 0.3f));
    EXPECT_NEAR(h.u, b.u, 1e-6f);
    EXPECT_NEAR(h.v, b.v, 1e-6f);
}

TEST_P(EmbreeTracerTest, IntervalIsInclusiveAtBothEnds) {
    const Scene scene = one_triangle();
    auto embree = make_embree_tracer(GetParam());
    embree->build(scene, 0);
    // The hit lies at t = 1 exactly (origin z = 1, plane z = 0, unit direction).
    EXPECT_TRUE(trace_one(*embree, down_at(0.25f, 0.25f, 0.0f, 1.0f)).found());
    EXPECT_TRUE(trace_one(*embree, down_at(0.25f, 0.25f, 1.0f, 2.0f)).found());
    EXPECT_FALSE(trace_one(*embree, down_at(0.25f, 0.25f, 0.0f, 0.999f)).found());
    EXPECT_FALSE(trace_one(*embree, down_at(0.25f, 0.25f, 1.001f, 2.0f)).found());
    EXPECT_TRUE(occluded_one(*embree, down_at(0.25f, 0.25f, 0.0f, 1.0f)));
    EXPECT_TRUE(occluded_one(*embree, down_at(0.25f, 0.25f, 1.0f, 2.0f)));
    EXPECT_FALSE(occluded_one(*embree, down_at(0.25f, 0.25f, 0.0f, 0.999f)));
    EXPECT_FALSE(occluded_one(*embree, down_at(0.25f, 0.25f, 1.001f, 2.0f)));
    EXPECT_FALSE(occluded_one(*embree, down_at(0.9f, 0.9f)));  // beside the triangle
}

/// How far `b` agrees with `a` on one ray set: occlusion for an any-hit set, closest hits else.
Agreement agreement_on(const RaySet& set, const Tracer& a, const Tracer& b) {
    if (set.any_hit) {
        std::vector<uint8_t> x(set.rays.size()), y(set.rays.size());
        a.occluded(set.rays, x, 0);
        b.occluded(set.rays, y, 0);
        return compare_occlusion(x, y);
    }
    std::vector<Hit> x(set.rays.size()), y(set.rays.size());
    a.trace(set.rays, x, 0, set.coherent);
    b.trace(set.rays, y, 0, set.coherent);
    return compare_hits(x, y);
}

TEST_P(EmbreeTracerTest, AnswersLikeBruteForceOnTheCornellBox) {
    const Scene scene = load_scene("cornell");
    const std::vector<RaySet> sets = bench_sets(scene, 64, 48);

    auto embree = make_embree_tracer(GetParam());
    embree->build(scene, 0);
    auto brute = make_accel_tracer("brute");
    brute->build(scene, 1);
    for (const RaySet& set : sets) {
        SCOPED_TRACE(set.name);
        ASSERT_FALSE(set.rays.empty());
        const Agreement agreement = agreement_on(set, *embree, *brute);
        EXPECT_GE(agreement.percent(), 99.5);
        if (!set.any_hit) {
            EXPECT_LT(agreement.max_dt_rel, 1e-4);
        }
    }
}

// Thicket's default structures answer every ray of the bench's four sets on a real scene like
// Embree: the same hit or miss, the same primitive or one at the same distance (Embree's triangle
// test rounds differently, so its t may differ in the last bits), the same occlusion.
TEST_P(EmbreeTracerTest, DefaultStructuresAgreeOnEveryRayOfSponza) {
    const std::string path = std::string(THICKET_SHARED_SCENES) + "/sponza-dabrovic.ply";
    if (!std::ifstream(path)) GTEST_SKIP() << path << " not found: the real-scene agreement test needs ../shared";
    const Scene scene = load_scene(path);
    const std::vector<RaySet> sets = bench_sets(scene, 160, 120);
    auto embree = make_embree_tracer(GetParam());
    embree->build(scene, 0);
    for (const char* spec : {"bvh", "kdtree"}) {
        auto thicket = make_accel_tracer(spec);
        thicket->build(scene, 0);
        for (const RaySet& set : sets) {
            SCOPED_TRACE(std::string(spec) + ", " + set.name);
            ASSERT_GE(set.rays.size(), 10000u);
            const Agreement agreement = agreement_on(set, *embree, *thicket);
            EXPECT_EQ(agreement.agreeing, agreement.rays) << "first mismatch at ray " << agreement.first_mismatch;
            if (!set.any_hit) {
                EXPECT_LT(agreement.max_dt_rel, 1e-3);
            }
        }
    }
}

// bvh8 over the tree Embree's own builder writes (bvh8:tree=embree-*, the bench's tree/kernel
// split) answers every ray like brute force: the tree's boxes enclose its leaves (the kernels'
// culling is then exact) and every triangle is in some leaf. Cornell box, sponza (../shared),
// one triangle and the empty scene.
TEST_P(EmbreeTracerTest, Bvh8OnEmbreesTreeAnswersLikeBruteForce) {
    install_embree_tree_builder();
    const std::string spec = GetParam() == EmbreeQuality::High ? "bvh8:tree=embree-high" : "bvh8:tree=embree-medium";
    std::vector<Scene> scenes{load_scene("cornell"), one_triangle(), Scene{}};
    const std::string path = std::string(THICKET_SHARED_SCENES) + "/sponza-dabrovic.ply";
    if (std::ifstream(path)) scenes.push_back(load_scene(path));
    else std::printf("%s not found: sponza left out of this test\n", path.c_str());
    for (const Scene& scene : scenes) {
        SCOPED_TRACE(scene.name);
        auto tree = make_accel_tracer(spec);
        tree->build(scene, 0);
        if (scene.primitive_count() == 0) {
            EXPECT_FALSE(trace_one(*tree, down_at(0.2f, 0.2f)).found());
            continue;
        }
        if (scene.primitive_count() == 1) {
            EXPECT_EQ(trace_one(*tree, down_at(0.2f, 0.2f)).prim, 0u);
            EXPECT_TRUE(occluded_one(*tree, down_at(0.2f, 0.2f)));
            EXPECT_FALSE(trace_one(*tree, down_at(0.8f, 0.8f)).found());
            continue;
        }
        EXPECT_GT(tree->figures().nodes, 0u);
        const std::vector<RaySet> sets = bench_sets(scene, 64, 48);
        auto brute = make_accel_tracer("brute");
        brute->build(scene, 0);
        for (const RaySet& set : sets) {
            SCOPED_TRACE(set.name);
            const Agreement agreement = agreement_on(set, *tree, *brute);
            EXPECT_EQ(agreement.agreeing, agreement.rays) << "first mismatch at ray " << agreement.first_mismatch;
            if (!set.any_hit) {
                EXPECT_EQ(agreement.max_dt_rel, 0.0);  // the same triangle test: the same t
            }
        }
    }
}

// The bench's Embree rows trace Embree's own instances: checked here against brute force over
// the flattened scene (not against a Thicket structure), with identity, mirrored, sheared and
// scaled instances of the Cornell box, so that a transform the tracer ignores or
// applies twice shows. The only rays forgiven are those the rounding arbiter settles (an edge
// ray), and they are few.
TEST_P(EmbreeTracerTest, InstancesAnswerLikeBruteForceOverTheFlattenedScene) {
    Scene scene = load_scene("cornell");
    const uint32_t geometries = scene.geometry_count();
    ASSERT_GE(geometries, 1u);
    for (uint32_t g = 0; g < geometries; ++g) {
        scene.add_instance(g, Affine{});
        Affine mirror;  // x mirrored about x = 1.5, beside the original
        mirror.m[0][0] = -1.0f;
        mirror.m[0][3] = 3.2f;
        scene.add_instance(g, mirror);
        Affine sheared;  // turned 0.5 rad about y, sheared x by y, scaled 0.7, lifted
        const float c = 0.7f * std::cos(0.5f), sn = 0.7f * std::sin(0.5f);
        sheared.m[0][0] = c, sheared.m[0][1] = 0.21f, sheared.m[0][2] = sn, sheared.m[0][3] = -1.5f;
        sheared.m[1][1] = 0.7f, sheared.m[1][3] = 1.2f;
        sheared.m[2][0] = -sn, sheared.m[2][2] = c, sheared.m[2][3] = 0.3f;
        scene.add_instance(g, sheared);
    }
    Scene prototypes = scene;
    prototypes.instances.clear();
    prototypes.instance_first.clear();
    const Scene flat = flatten_instances(prototypes, scene.instances);
    ASSERT_EQ(flat.primitive_count(), scene.instanced_primitive_count());
    const std::vector<RaySet> sets = bench_sets(flat, 96, 64);
    auto embree = make_embree_tracer(GetParam());
    embree->build(scene, 0);
    auto brute = make_accel_tracer("brute");
    brute->build(flat, 1);
    const RoundingArbiter arbiter(scene);
    for (const RaySet& set : sets) {
        SCOPED_TRACE(set.name);
        Agreement a;
        if (set.any_hit) {
            std::vector<uint8_t> want(set.rays.size()), got(set.rays.size());
            brute->occluded(set.rays, want, 0);
            embree->occluded(set.rays, got, 0);
            a = compare_occlusion(want, got, {}, [&](size_t i) {
                const Hit r = trace_one(*brute, set.rays[i]), c = trace_one(*embree, set.rays[i]);
                return arbiter.occlusion_within_rounding(set.rays[i], got[i] != 0, r, c);
            });
        } else {
            std::vector<Hit> want(set.rays.size()), got(set.rays.size());
            brute->trace(set.rays, want, 0, false);
            embree->trace(set.rays, got, 0, false);
            a = compare_hits(want, got, {}, {}, [&](size_t i, const Hit& r, const Hit& c) {
                return arbiter.candidate_within_rounding(set.rays[i], r, c);
            });
        }
        std::printf("[ instances] %s: %zu of %zu rays agree, %zu of them settled by the arbiter\n", set.name.c_str(),
                    a.agreeing, a.rays, a.arbitrated);
        EXPECT_EQ(a.disagreeing(), 0u);
        EXPECT_LE(a.arbitrated, a.rays / 200) << "more edge rays than rounding makes";
    }
}

TEST_P(EmbreeTracerTest, CountsItsMemoryAndNamesItself) {
    const Scene scene = load_scene("cornell");
    auto embree = make_embree_tracer(GetParam());
    EXPECT_THROW(trace_one(*embree, down_at(0, 0)), Error);
    EXPECT_TRUE(embree->parallel_build());
    const double ms = embree->build(scene, 1);
    EXPECT_GE(ms, 0.0);
    const TracerFigures f = embree->figures();
    EXPECT_EQ(f.primitives, scene.primitive_count());
    EXPECT_GT(f.bytes, 0u);
    EXPECT_NE(f.spec.find("embree"), std::string::npos);
    EXPECT_EQ(embree->name(), GetParam() == EmbreeQuality::High ? "embree-high" : "embree-medium");
    RayCounters c;
    EXPECT_FALSE(embree->count({}, false, c, 1));
}

TEST(EmbreeTracer, EmptySceneMissesEverything) {
    const Scene empty;
    auto embree = make_embree_tracer(EmbreeQuality::High);
    embree->build(empty, 1);
    EXPECT_FALSE(trace_one(*embree, down_at(0.2f, 0.2f)).found());
    EXPECT_FALSE(occluded_one(*embree, down_at(0.2f, 0.2f)));
    EXPECT_FALSE(embree_version().empty());
}

INSTANTIATE_TEST_SUITE_P(Qualities, EmbreeTracerTest, ::testing::Values(EmbreeQuality::Medium, EmbreeQuality::High),
                         [](const auto& info) { return std::string(embree_tracer_name(info.param) + 7); });

}  // namespace
