// builder=ploc: valid trees whose leaves follow the other builders' rules, the same tree on any
// number of threads, a tree tighter than the Morton builder's it starts from, and work that grows
// linearly with the primitives (counted: areas evaluated, clusters visited), even on a chain that
// agrees on one pair a round.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <random>
#include <vector>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh/ploc.h"
#include "thicket/scene/scene.h"

namespace thicket::ploc_test {
namespace {

/// Boxes of `count` small random triangles in clusters, every eighth collapsed to a point and a
/// few with NaN corners; their centroids alongside.
struct Boxes {
    std::vector<Aabb> bounds;
    std::vector<Vec3> centroids;
    BuildPrimitives prims() const { return {bounds, centroids}; }
};

Boxes random_boxes(int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Boxes b;
    for (int i = 0; i < count; ++i) {
        const Vec3 c = Vec3(float(i % 3) * 5.0f, 0.0f, 0.0f) + Vec3(u(rng), u(rng), u(rng));
        Aabb box;
        box.grow(c);
        if (i % 8 != 1) box.grow(c + Vec3(u(rng), u(rng), u(rng)) * 0.02f);
        if (i % 997 == 5) box.grow(Vec3(std::nanf(""), 0.0f, 0.0f));
        b.bounds.push_back(box);
        b.centroids.push_back(box.center());
    }
    return b;
}

BvhBuildOptions ploc_options(uint32_t radius, int max_leaf, uint32_t block, unsigned threads) {
    BvhBuildOptions o;
    o.builder = BvhBuilder::Ploc;
    o.ploc_radius = radius;
    o.max_leaf = max_leaf;
    o.sah_block = block;
    o.threads = threads;
    return o;
}

/// Largest leaf of a valid tree.
uint32_t largest_leaf(const BvhData& bvh) {
    uint32_t largest = 0;
    for (uint32_t n = 0; n < bvh.nodes_used; ++n)
        if (n != 1) largest = std::max(largest, bvh.nodes[n].count);
    return largest;
}

TEST(Ploc, ValidTreesWithLeavesWithinMaxLeafForEveryRadiusAndBlock) {
    for (int count : {1, 2, 3, 40, 5000}) {
        const Boxes b = random_boxes(count, unsigned(count));
        for (uint32_t radius : {1u, 2u, 16u})
            for (int max_leaf : {1, 4, 8})
                for (uint32_t block : {1u, 4u}) {
                    const BvhData bvh = build_bvh(b.prims(), ploc_options(radius, max_leaf, block, 2));
                    const std::string what = std::to_string(count) + " boxes, radius " + std::to_string(radius) +
                                             ", max-leaf " + std::to_string(max_leaf);
                    ASSERT_NO_THROW(validate_bvh(bvh, b.bounds.size())) << what;
                    ASSERT_NO_THROW(validate_bvh_bounds(bvh, b.bounds)) << what;
                    EXPECT_LE(largest_leaf(bvh), uint32_t(max_leaf)) << what;
                    if (count > 100) {
                        EXPECT_GT(bvh.nodes_used, 2u * uint32_t(count) / uint32_t(max_leaf) / 4) << what;
                    }
                }
    }
}

TEST(Ploc, SameTreeOnOneTwoAndSevenThreadsAndTwice) {
    // Several round chunks (2048 positions) in the first rounds.
    const Boxes b = random_boxes(20000, 7);
    const BvhData one = build_bvh(b.prims(), ploc_options(16, 4, 4, 1));
    for (unsigned threads : {1u, 2u, 7u}) {
        const BvhData other = build_bvh(b.prims(), ploc_options(16, 4, 4, threads));
        ASSERT_EQ(one.nodes_used, other.nodes_used) << threads;
        EXPECT_EQ(0, std::memcmp(one.nodes.data(), other.nodes.data(), one.nodes_used * sizeof(BvhNode))) << threads;
        EXPECT_EQ(one.prim_indices, other.prim_indices) << threads;
        EXPECT_EQ(one.child_order, other.child_order) << threads;
    }
}

TEST(Ploc, TighterThanTheMortonTreeItClustersAlong) {
    const Boxes b = random_boxes(20000, 3);
    BvhBuildOptions lbvh = ploc_options(16, 4, 1, 2);
    lbvh.builder = BvhBuilder::Lbvh;
    const double morton = bvh_figures(build_bvh(b.prims(), lbvh)).sah_cost;
    const double ploc = bvh_figures(build_bvh(b.prims(), ploc_options(16, 4, 1, 2))).sah_cost;
    const double near = bvh_figures(build_bvh(b.prims(), ploc_options(1, 4, 1, 2))).sah_cost;
    EXPECT_LT(ploc, 0.9 * morton) << "lbvh " << morton << ", ploc " << ploc;
    EXPECT_LE(ploc, near) << "a wider search found worse neighbours";
}

TEST(Ploc, WorkGrowsLinearlyAndEachClusterComputesAtMostRadiusAreasPerRound) {
    const uint32_t radius = 8;
    double per_primitive[2] = {};
    int k = 0;
    for (int count : {4000, 32000}) {
        const Boxes b = random_boxes(count, 5);
        PlocCounts c;
        build_ploc(b.prims(), ploc_options(radius, 4, 4, 2), &c);
        // Each pair of a chunk's window once: radius per cluster, plus the window's edge.
        EXPECT_LE(c.distance_evaluations, uint64_t(radius) * c.cluster_visits + uint64_t(radius) * radius * 64 * c.iterations)
            << count;
        EXPECT_GE(c.distance_evaluations, uint64_t(radius) * (c.cluster_visits - uint64_t(radius) * c.iterations))
            << count;
        // Rounds remove a fixed share of the clusters: visits are a few n, rounds a few log n.
        EXPECT_LE(c.cluster_visits, 5u * uint64_t(count)) << count;
        EXPECT_LE(c.iterations, 60u) << count;
        EXPECT_EQ(c.forced_rounds, 0u) << count;
        per_primitive[k++] = double(c.distance_evaluations) / count;
    }
    // Eight times the primitives, about eight times the work (not n log n).
    EXPECT_LT(per_primitive[1], 1.15 * per_primitive[0]) << per_primitive[0] << " then " << per_primitive[1];
}

TEST(Ploc, AChainOfWideningGapsIsPairedInOrderNotOnePairARound) {
    // Points at i^2 on a line: every point's nearest is its left neighbour, so only the first
    // pair is mutual each round.
    Boxes b;
    const int count = 3000;
    for (int i = 0; i < count; ++i) {
        Aabb box;
        box.grow(Vec3(float(i) * float(i), 0.0f, 0.0f));
        box.grow(Vec3(float(i) * float(i), 1.0f, 1.0f));  // a unit square: merged areas grow with the gap
        b.bounds.push_back(box);
        b.centroids.push_back(box.center());
    }
    PlocCounts c;
    const BvhData bvh = build_ploc(b.prims(), ploc_options(4, 1, 1, 2), &c);
    ASSERT_NO_THROW(validate_bvh(bvh, b.bounds.size()));
    ASSERT_NO_THROW(validate_bvh_bounds(bvh, b.bounds));
    EXPECT_GT(c.forced_rounds, 0u);
    EXPECT_LE(c.cluster_visits, 5u * uint64_t(count));
    EXPECT_LE(c.iterations, 100u);
}

/// Small random triangles in clusters (as random_boxes), none degenerate.
Scene clustered_triangles(int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Scene scene;
    for (int i = 0; i < count; ++i) {
        const Vec3 c = Vec3(float(i % 5) * 3.0f, float(i % 2) * 2.0f, 0.0f) + Vec3(u(rng), u(rng), u(rng));
        const uint32_t base = uint32_t(scene.mesh.positions.size());
        scene.mesh.positions.insert(scene.mesh.positions.end(),
                                    {c, c + Vec3(0.04f * u(rng), 0.04f, 0.0f), c + Vec3(0.0f, 0.04f * u(rng), 0.04f)});
        scene.mesh.indices.insert(scene.mesh.indices.end(), {base, base + 1, base + 2});
    }
    return scene;
}

// Child order in PLOC's tree (issue 45): it is built bottom up, and each pair's order byte says
// which child the ordered traversals enter first. A wrong byte answers right and visits far
// children first, so it is counted: the traversals that read the byte (ordered-axis, ordered-
// centroid) visit about what ordered-distance visits on the same tree (it compares the children's
// entry distances and reads no byte). Planted: PLOC storing axis 0 for every pair fails it.
TEST(Ploc, ItsChildOrderLeadsOrderedTraversalsNearlyAsWellAsEntryDistances) {
    const Scene scene = clustered_triangles(20000, 11);
    const std::vector<Ray> rays = testing::conformance_rays(scene, 4000, 2);
    const auto visits = [&](const std::string& spec) {
        const auto accel = build_accel(spec, scene);
        RayCounters c;
        for (const Ray& r : rays) accel->intersect(r, c);
        return double(c.nodes);
    };
    for (const char* options : {"", ",max-leaf=1,radius=1"}) {
        const double distance = visits(std::string("bvh:builder=ploc,traversal=ordered-distance") + options);
        for (const char* traversal : {"ordered-axis", "ordered-centroid"}) {
            const std::string spec = std::string("bvh:builder=ploc,traversal=") + traversal + options;
            const double v = visits(spec);
            std::printf("[ order    ] %s: %.0f nodes, ordered-distance %.0f\n", spec.c_str(), v, distance);
            EXPECT_LE(v, 1.05 * distance) << spec;
        }
    }
}

}  // namespace
}  // namespace thicket::ploc_test
