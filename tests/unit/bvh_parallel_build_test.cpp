// The parallel BVH build: the same tree, byte for byte, on any number of threads, and a tree as
// valid and tight as the single-threaded one.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "thicket/accel/registry.h"
#include "thicket/bvh/bvh.h"
#include "thicket/prims/triangles.h"

namespace thicket::bvh_parallel_build_test {
namespace {

/// Big enough that several levels are top nodes (kParallelNodeSize) split by all threads:
/// clusters of random triangles, and a block of identical centroids bigger than a top node, so
/// that the fallback median split also runs on a top node.
Scene big_scene() {
    TriangleMesh m;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto add = [&](Vec3 c, float size) {
        const auto base = uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {c, c + Vec3(size, 0, 0), c + Vec3(0, size, size * 0.3f)});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    };
    for (int i = 0; i < 90000; ++i) {
        const Vec3 cluster = Vec3(float(i % 5) * 40.0f, float(i % 3) * 25.0f, 0.0f);
        add(cluster + Vec3(u(rng), u(rng), u(rng)) * (i % 2 ? 10.0f : 3.0f), 0.05f + 0.2f * u(rng));
    }
    for (int i = 0; i < 2 * int(kParallelNodeSize); ++i) add(Vec3(500.0f, 500.0f, 500.0f), 1.0f);
    Scene scene;
    scene.name = "parallel-build";
    scene.mesh = m;
    return scene;
}

BvhData build(const Scene& scene, BvhBuildOptions o, unsigned threads) {
    o.threads = threads;
    return Bvh<Triangles<>>(Triangles<>(scene.mesh), o).data();
}

void expect_identical(const BvhData& a, const BvhData& b, const std::string& what) {
    ASSERT_EQ(a.nodes_used, b.nodes_used) << what;
    EXPECT_EQ(0, std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes_used * sizeof(BvhNode))) << what << ": nodes";
    EXPECT_EQ(a.prim_indices, b.prim_indices) << what << ": primitive order";
    EXPECT_EQ(0, std::memcmp(a.child_order.data(), b.child_order.data(), a.nodes_used)) << what << ": order bytes";
}

struct Case {
    const char* name;
    BvhBuildOptions options;
};

std::vector<Case> cases() {
    return {{"midpoint", {BvhBuilder::Midpoint, 8, 8}},
            {"binned-sah bins=8", {BvhBuilder::BinnedSah, 8, 8}},
            {"binned-sah bins=32 max-leaf=1", {BvhBuilder::BinnedSah, 32, 1}},
            {"sweep-sah", {BvhBuilder::SweepSah, 8, 4}},
            {"lbvh", {BvhBuilder::Lbvh, 8, 4}}};
}

TEST(BvhParallelBuild, SameTreeByteForByteOnOneTwoAndSevenThreads) {
    const Scene scene = big_scene();
    for (const Case& c : cases()) {
        const BvhData one = build(scene, c.options, 1);
        ASSERT_NO_THROW(validate_bvh(one, scene.primitive_count())) << c.name;
        for (unsigned threads : {2u, 7u}) expect_identical(one, build(scene, c.options, threads), std::string(c.name) + ", " + std::to_string(threads) + " threads");
    }
}

TEST(BvhParallelBuild, TopNodesAreTightAndEveryPrimitiveIsInOneLeaf) {
    const Scene scene = big_scene();
    const Triangles<> tris(scene.mesh);
    for (const Case& c : cases()) {
        const BvhData d = build(scene, c.options, 3);
        ASSERT_NO_THROW(validate_bvh(d, scene.primitive_count())) << c.name;
        EXPECT_EQ(bvh_figures(d).nodes, d.nodes_used - 1) << c.name << ": every node but slot 1 is reachable";
        EXPECT_LE(bvh_figures(d).max_leaf_size, size_t(c.options.max_leaf)) << c.name;
        size_t wrong = 0;
        for (uint32_t n = 0; n < d.nodes_used; ++n) {
            if (n == 1) continue;
            const BvhNode& node = d.nodes[n];
            Aabb want;
            if (node.is_leaf()) {
                for (uint32_t i = 0; i < node.count; ++i) want.grow(tris.bounds(d.prim_indices[node.leftFirst + i]));
            } else {
                want.grow(d.nodes[node.leftFirst].bounds());
                want.grow(d.nodes[node.leftFirst + 1].bounds());
            }
            wrong += !(node.aabbMin == want.min && node.aabbMax == want.max);
        }
        EXPECT_EQ(wrong, 0u) << c.name << ": nodes whose box is not the union of their contents";
    }
}

TEST(BvhParallelBuild, ThreadsReachTheBuilderThroughBuildAccelAndTheBenchSeesIt) {
    const Scene scene = big_scene();
    for (const char* spec : {"bvh", "bvh8"}) {
        const auto a = build_accel(spec, scene, 1);
        const auto b = build_accel(spec, scene, 2);
        EXPECT_EQ(a->stats().sah_cost, b->stats().sah_cost) << spec;
        EXPECT_EQ(a->stats().nodes, b->stats().nodes) << spec;
        EXPECT_EQ(a->spec(), b->spec()) << spec << ": the thread count is not part of the spec";
        EXPECT_TRUE(find_accel(spec)->threaded_build) << spec;
    }
    EXPECT_FALSE(find_accel("kdtree")->threaded_build);
}

}  // namespace
}  // namespace thicket::bvh_parallel_build_test
