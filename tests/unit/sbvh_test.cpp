// The spatial-split builder (builder=sbvh, Stich et al. 2009): on long thin diagonal triangles,
// whose boxes overlap whatever object split is made, it beats the object-partition SAH builders by
// cutting triangles, within its reference budget; budget=0 cuts nothing; the tree is the same on
// every build and thread count; saved and reloaded it answers as built; counting queries count a
// triangle listed in several leaves once; the load validator refuses a tree that loses a part.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh/bvh.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"

namespace thicket::sbvh_test {
namespace {

/// `count` long thin triangles along the cube's diagonals (length ~8 in a box of 10, width 0.02):
/// their boxes are nearly as big as the scene, the case spatial splits exist for.
Scene diagonal_slivers(int count = 400) {
    TriangleMesh m;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < count; ++i) {
        const Vec3 d(i & 1 ? 1.0f : -1.0f, i & 2 ? 1.0f : -1.0f, 1.0f);
        const Vec3 start = Vec3(5, 5, 1) - d * 4.0f + Vec3(u(rng), u(rng), u(rng)) * 2.0f;
        const Vec3 end = start + d * (4.0f + 4.0f * u(rng));
        const auto base = uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {start, end, end + Vec3(0.02f, -0.02f, 0.0f)});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    Scene scene;
    scene.name = "diagonal-slivers";
    scene.mesh = m;
    return scene;
}

const Bvh<Triangles<>>& as_bvh(const Accel& a) { return dynamic_cast<const Bvh<Triangles<>>&>(a); }

std::string extra(const AccelStats& s, const std::string& key) {
    for (const auto& [k, v] : s.extra)
        if (k == key) return v;
    return "";
}

size_t references(const Accel& a) { return std::stoull(extra(a.stats(), "references")); }

TEST(Sbvh, CutsDiagonalSliversForALowerSahCostWithinItsBudget) {
    const Scene scene = diagonal_slivers();
    const size_t n = scene.primitive_count();
    const auto binned = build_accel("bvh:builder=binned-sah", scene);
    const auto sweep = build_accel("bvh:builder=sweep-sah", scene);
    const auto sbvh = build_accel("bvh:builder=sbvh", scene);
    EXPECT_LT(sbvh->stats().sah_cost, binned->stats().sah_cost);
    EXPECT_LT(sbvh->stats().sah_cost, sweep->stats().sah_cost);
    EXPECT_GT(references(*sbvh), n) << "no triangle was cut";
    EXPECT_LE(references(*sbvh), n + size_t(0.3 * double(n))) << "over the default budget 0.3";
    EXPECT_EQ(references(*binned), n);
    // A bigger budget is honoured too.
    const auto generous = build_accel("bvh:builder=sbvh,budget=1", scene);
    EXPECT_GT(references(*generous), references(*sbvh));
    EXPECT_LE(references(*generous), 2 * n);
    // alpha=1: no node's children overlap by the root's whole area, so no spatial split is tried.
    EXPECT_EQ(references(*build_accel("bvh:builder=sbvh,alpha=1", scene)), n);
    std::printf("[ sbvh ] slivers: SAH binned %.2f, sweep %.2f, sbvh %.2f (%zu references for %zu), budget=1 %.2f (%zu)\n",
                binned->stats().sah_cost, sweep->stats().sah_cost, sbvh->stats().sah_cost, references(*sbvh), n,
                generous->stats().sah_cost, references(*generous));
}

TEST(Sbvh, BudgetZeroMakesNoSpatialSplit) {
    const Scene scene = diagonal_slivers();
    const auto accel = build_accel("bvh:builder=sbvh,budget=0", scene);
    const BvhData& d = as_bvh(*accel).data();
    EXPECT_EQ(d.prim_indices.size(), scene.primitive_count());
    ASSERT_NO_THROW(validate_bvh(d, scene.primitive_count()));
    // Every primitive in exactly one leaf whose box holds all of it: a plain object-split tree.
    const Triangles<> tris(scene.mesh);
    std::vector<Aabb> bounds;
    for (uint32_t i = 0; i < tris.size(); ++i) bounds.push_back(tris.bounds(i));
    EXPECT_NO_THROW(validate_bvh_bounds(d, bounds));
    std::vector<uint32_t> sorted = d.prim_indices;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
}

TEST(Sbvh, SameTreeOnEveryBuildAndThreadCount) {
    const Scene scene = diagonal_slivers();
    BvhBuildOptions o;
    o.builder = BvhBuilder::Sbvh;
    o.max_leaf = 4;
    auto build = [&](unsigned threads) {
        o.threads = threads;
        return Bvh<Triangles<>>(Triangles<>(scene.mesh), o).data();
    };
    const BvhData a = build(1);
    ASSERT_GT(a.prim_indices.size(), scene.primitive_count());
    for (unsigned threads : {1u, 2u, 7u}) {
        const BvhData b = build(threads);
        ASSERT_EQ(a.nodes_used, b.nodes_used) << threads;
        EXPECT_EQ(0, std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes_used * sizeof(BvhNode))) << threads;
        EXPECT_EQ(a.prim_indices, b.prim_indices) << threads;
        EXPECT_EQ(0, std::memcmp(a.child_order.data(), b.child_order.data(), a.nodes_used)) << threads;
    }
}

TEST(Sbvh, SavedAndReloadedAnswersAsBuiltAndLikeBruteForce) {
    const Scene scene = diagonal_slivers();
    const auto brute = build_accel("brute", scene);
    for (const char* spec : {"bvh:builder=sbvh", "bvh:builder=sbvh,budget=2,max-leaf=1,optimize=reinsertion"}) {
        const auto built = build_accel(spec, scene);
        ASSERT_GT(references(*built), scene.primitive_count()) << spec;
        const auto loaded = load_accel_bytes(saved_accel_bytes(*built, scene), scene, "sbvh.bin");
        EXPECT_EQ(references(*loaded), references(*built));
        EXPECT_EQ(as_bvh(*loaded).data().prim_indices, as_bvh(*built).data().prim_indices);
        size_t hits = 0;
        for (const Ray& r : testing::conformance_rays(scene, 2000, 3)) {
            const Hit a = built->intersect(r), b = loaded->intersect(r), want = brute->intersect(r);
            ASSERT_EQ(a.prim, b.prim) << spec;
            ASSERT_EQ(a.t, b.t) << spec;
            ASSERT_EQ(a.found(), want.found()) << spec;
            if (a.found()) {
                ASSERT_NEAR(a.t, want.t, 1e-5f * want.t) << spec;  // the suite's rule
            }
            ASSERT_EQ(loaded->occluded(r), brute->occluded(r)) << spec;
            hits += a.found();
        }
        EXPECT_GT(hits, 100u);
    }
}

// all_hits/count_hits (the Python module's list_intersections/count_intersections) count surface
// crossings: a triangle listed in several leaves, reached through more than one of them, is still
// one crossing. Rays along the slivers' length cross many leaves of the same triangles.
TEST(Sbvh, CountingQueriesCountATriangleInSeveralLeavesOnce) {
    const Scene scene = diagonal_slivers(200);
    const auto brute = build_accel("brute", scene);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 10.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 o(u(rng), u(rng), -2.0f), target(u(rng), u(rng), 12.0f);
        rays.push_back({o, 0.0f, target - o, kInfinity});
    }
    for (const Ray& r : testing::conformance_rays(scene, 1000, 9)) rays.push_back(r);
    for (const char* spec : {"bvh:builder=sbvh,budget=2,max-leaf=1", "bvh8:builder=sbvh,budget=2",
                             "bvh8:budget=2,quality=high"}) {
        const auto accel = build_accel(spec, scene);
        ASSERT_GT(references(*accel), scene.primitive_count()) << spec;
        size_t crossings = 0;
        for (const Ray& r : rays) {
            const uint32_t want = brute->count_hits(r);
            ASSERT_EQ(accel->count_hits(r), want) << spec;
            std::vector<Hit> got, expected;
            accel->all_hits(r, got);
            brute->all_hits(r, expected);
            ASSERT_EQ(got.size(), expected.size()) << spec;
            for (size_t k = 0; k < got.size(); ++k) ASSERT_EQ(got[k].t, expected[k].t) << spec;
            crossings += want;
        }
        EXPECT_GT(crossings, 500u) << spec;
    }
}

TEST(Sbvh, TheLoadValidatorRefusesATreeThatLosesAPartOfATriangle) {
    const Scene scene = diagonal_slivers();
    const auto accel = build_accel("bvh:builder=sbvh,budget=1", scene);
    BvhData d = as_bvh(*accel).data();
    const Triangles<> tris(scene.mesh);
    std::vector<Aabb> bounds;
    for (uint32_t i = 0; i < tris.size(); ++i) bounds.push_back(tris.bounds(i));
    const ClipFunction clip = [&](uint32_t i, const Aabb& box) { return tris.clip(i, box); };
    ASSERT_NO_THROW(validate_bvh_bounds(d, bounds, clip));
    // A triangle listed twice: replace one of its entries by another triangle of the same leaf,
    // so what that leaf held of it is lost. Where points of the triangle are then in none of
    // the boxes still listing it, the validator must refuse the tree.
    std::vector<uint32_t> count(scene.primitive_count(), 0);
    for (uint32_t p : d.prim_indices) ++count[p];
    size_t losing = 0;
    for (uint32_t n = 0; n < d.nodes_used; ++n) {
        const BvhNode& node = d.nodes[n];
        if (n == 1 || !node.is_leaf() || node.count < 2) continue;
        for (uint32_t k = node.leftFirst; k < node.leftFirst + node.count; ++k) {
            const uint32_t prim = d.prim_indices[k];
            if (count[prim] != 2) continue;
            BvhData broken = d;
            broken.prim_indices[k] = d.prim_indices[k == node.leftFirst ? k + 1 : node.leftFirst];
            ASSERT_NO_THROW(validate_bvh(broken, scene.primitive_count()));  // well formed: only coverage is lost
            // The leaf still listing it, and points of the triangle on a fine barycentric grid.
            Aabb kept;
            for (uint32_t m = 0; m < broken.nodes_used; ++m)
                if (m != 1 && broken.nodes[m].is_leaf())
                    for (uint32_t e = 0; e < broken.nodes[m].count; ++e)
                        if (broken.prim_indices[broken.nodes[m].leftFirst + e] == prim) kept = broken.nodes[m].bounds();
            // Clearly outside (1e-3, far beyond rounding), so that the loss is not in doubt.
            kept.min = kept.min - Vec3(1e-3f, 1e-3f, 1e-3f);
            kept.max = kept.max + Vec3(1e-3f, 1e-3f, 1e-3f);
            const auto v = tris.triangle(prim);
            bool lost = false;
            for (int i = 0; i <= 64 && !lost; ++i)
                for (int j = 0; i + j <= 64 && !lost; ++j) {
                    const float a = float(i) / 64.0f, b = float(j) / 64.0f;
                    const Vec3 q = v[0] + (v[1] - v[0]) * a + (v[2] - v[0]) * b;
                    lost = !kept.contains(q);
                }
            if (!lost) continue;
            ++losing;
            EXPECT_THROW(validate_bvh_bounds(broken, bounds, clip), Error) << "primitive " << prim;
            if (losing >= 20) break;
        }
        if (losing >= 20) break;
    }
    EXPECT_GT(losing, 0u);
}

}  // namespace
}  // namespace thicket::sbvh_test
