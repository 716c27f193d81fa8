// optimize=reinsertion: never raises the SAH cost, lowers it where the builder left room, keeps
// every leaf as built, and leaves a valid tree in the lecture's layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh/bvh.h"
#include "thicket/bvh/reinsertion.h"
#include "thicket/prims/triangles.h"

namespace thicket::bvh_reinsertion_test {
namespace {

Scene clustered(int triangles) {
    TriangleMesh m;
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < triangles; ++i) {
        const Vec3 c = Vec3{float(i % 7) * 9.0f, float(i % 3) * 4.0f, 0.0f} + Vec3{u(rng), u(rng), u(rng)} * 3.0f;
        const float s = 0.02f + 0.5f * u(rng) * u(rng);
        const auto base = uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {c, c + Vec3{s, 0, 0}, c + Vec3{0, s, s}});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    Scene scene;
    scene.mesh = m;
    return scene;
}

BvhData build(const Scene& scene, BvhBuilder builder, BvhOptimize optimize, int max_leaf = 4) {
    BvhBuildOptions o;
    o.builder = builder;
    o.max_leaf = max_leaf;
    o.optimize = optimize;
    return Bvh<Triangles<>>(Triangles<>(scene.mesh), o).data();
}

/// Each leaf's primitives, sorted, as one sorted list of lists: what reinsertion must not change.
std::vector<std::vector<uint32_t>> leaves(const BvhData& d) {
    std::vector<std::vector<uint32_t>> out;
    for (uint32_t n = 0; n < d.nodes_used; ++n) {
        if (n == 1 || !d.nodes[n].is_leaf()) continue;
        std::vector<uint32_t> l(d.prim_indices.begin() + d.nodes[n].leftFirst,
                                d.prim_indices.begin() + d.nodes[n].leftFirst + d.nodes[n].count);
        std::sort(l.begin(), l.end());
        out.push_back(l);
    }
    std::sort(out.begin(), out.end());
    return out;
}

TEST(BvhReinsertion, NeverRaisesTheSahCostAndKeepsEveryLeaf) {
    std::vector<Scene> scenes = testing::nasty_scenes();
    scenes.push_back(clustered(5000));
    for (const Scene& scene : scenes) {
        for (BvhBuilder b : {BvhBuilder::Midpoint, BvhBuilder::BinnedSah, BvhBuilder::SweepSah, BvhBuilder::Lbvh}) {
            const BvhData plain = build(scene, b, BvhOptimize::None);
            const BvhData opt = build(scene, b, BvhOptimize::Reinsertion);
            ASSERT_NO_THROW(validate_bvh(opt, plain.prim_indices.size())) << scene.name;
            if (plain.nodes_used == 0) continue;
            EXPECT_LE(bvh_figures(opt).sah_cost, bvh_figures(plain).sah_cost) << scene.name;
            EXPECT_EQ(leaves(opt), leaves(plain)) << scene.name;
            EXPECT_EQ(bvh_figures(opt).nodes, opt.nodes_used - 1) << scene.name << ": every node reachable";
            EXPECT_LE(bvh_figures(opt).max_depth, size_t(kMaxSahDepth)) << scene.name;
            // Boxes are their children's union, and each pair's left child lies lower on its axis.
            for (uint32_t n = 0; n < opt.nodes_used; ++n) {
                const BvhNode& node = opt.nodes[n];
                if (n == 1 || node.is_leaf()) continue;
                Aabb want = opt.nodes[node.leftFirst].bounds();
                want.grow(opt.nodes[node.leftFirst + 1].bounds());
                EXPECT_TRUE(node.aabbMin == want.min && node.aabbMax == want.max) << scene.name << " node " << n;
            }
        }
    }
}

TEST(BvhReinsertion, LowersTheSahCostOfLooseTrees) {
    const Scene scene = clustered(20000);
    // The binned SAH tree is already close to what reinsertion reaches; the builders that never
    // look at the SAH leave room it must find.
    for (BvhBuilder b : {BvhBuilder::Midpoint, BvhBuilder::Lbvh}) {
        const double before = bvh_figures(build(scene, b, BvhOptimize::None)).sah_cost;
        const double after = bvh_figures(build(scene, b, BvhOptimize::Reinsertion)).sah_cost;
        EXPECT_LT(after, before * 0.995) << int(b) << ": " << before << " -> " << after;
    }
}

TEST(BvhReinsertion, TheSameTreeOnAnyNumberOfThreadsAndAllAnswersRight) {
    const Scene scene = clustered(40000);
    const auto one = build_accel("bvh:optimize=reinsertion", scene, 1);
    const auto two = build_accel("bvh:optimize=reinsertion", scene, 2);
    EXPECT_EQ(one->stats().sah_cost, two->stats().sah_cost);
    EXPECT_EQ(one->stats().nodes, two->stats().nodes);
}

}  // namespace
}  // namespace thicket::bvh_reinsertion_test
