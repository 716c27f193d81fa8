#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "support/probe.h"
#include "support/reference.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bih/bih.h"
#include "thicket/brute/brute_force.h"
#include "thicket/bvh/bvh.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"

namespace thicket::bih_test {
namespace {

Scene soup() { return testing::nasty_scenes().back(); }

Bih<Triangles<>> make_bih(const Scene& scene, int max_leaf = 4, BihEmptySide empty = BihEmptySide::Cut) {
    BihBuildOptions o;
    o.max_leaf = max_leaf;
    o.empty_side = empty;
    return Bih<Triangles<>>(Triangles<>(scene.mesh), o);
}

void add_triangle(TriangleMesh& m, Vec3 a, Vec3 b, Vec3 c) {
    const auto base = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

/// Bounds and box-centre bounds of the primitives under node n.
struct Subtree {
    Aabb bounds, centers;
    size_t count = 0;
};
Subtree subtree(const Bih<Triangles<>>& bih, uint32_t n) {
    Subtree s;
    const BihData& d = bih.data();
    std::vector<uint32_t> stack{n};
    while (!stack.empty()) {
        const BihNode& node = d.nodes[stack.back()];
        stack.pop_back();
        if (!node.is_leaf()) {
            stack.push_back(node.index());
            stack.push_back(node.index() + 1);
            continue;
        }
        for (uint32_t i = node.index(); i < node.index() + node.count(); ++i) {
            const Aabb b = bih.primitives().bounds(d.prim_indices[i]);
            s.bounds.grow(b);
            s.centers.grow(b.center());
            ++s.count;
        }
    }
    return s;
}

TEST(BihLayout, NodeIsTwelveBytes) {
    EXPECT_EQ(sizeof(BihNode), 12u);
    const BihNode inner = BihNode::inner(2, 12345, -1.5f, 2.25f);
    EXPECT_FALSE(inner.is_leaf());
    EXPECT_EQ(inner.axis(), 2);
    EXPECT_EQ(inner.index(), 12345u);
    EXPECT_EQ(inner.left_max(), -1.5f);
    EXPECT_EQ(inner.right_min(), 2.25f);
    const BihNode leaf = BihNode::leaf(kBihMaxIndex, 7);
    EXPECT_TRUE(leaf.is_leaf());
    EXPECT_EQ(leaf.index(), kBihMaxIndex);
    EXPECT_EQ(leaf.count(), 7u);
}

TEST(BihBuild, ClipPlanesAreTheChildrensActualExtremes) {
    const Scene scene = soup();
    for (BihEmptySide empty : {BihEmptySide::Cut, BihEmptySide::Refine})
        for (int max_leaf : {1, 4, 8}) {
            const auto bih = make_bih(scene, max_leaf, empty);
            const BihData& d = bih.data();
            ASSERT_NO_THROW(validate_bih(d, scene.primitive_count()));
            const BihFigures f = bih_figures(d);
            EXPECT_EQ(f.nodes, d.nodes.size()) << "every node is reachable";
            EXPECT_LE(f.max_leaf_size, size_t(max_leaf));
            if (empty == BihEmptySide::Refine) {
                EXPECT_EQ(f.empty_leaves, 0u);
            }
            for (uint32_t n = 0; n < d.nodes.size(); ++n) {
                const BihNode& node = d.nodes[n];
                if (node.is_leaf()) continue;
                const int a = node.axis();
                const Subtree left = subtree(bih, node.index()), right = subtree(bih, node.index() + 1);
                if (left.count == 0) {
                    EXPECT_EQ(node.left_max(), -kInfinity) << "an empty child is never entered";
                } else {
                    EXPECT_EQ(node.left_max(), left.bounds.max[a]) << "node " << n;
                }
                if (right.count == 0) {
                    EXPECT_EQ(node.right_min(), kInfinity);
                } else {
                    EXPECT_EQ(node.right_min(), right.bounds.min[a]) << "node " << n;
                }
                // The soup's centres all differ, so every split is a plane split: the left
                // side's centres lie strictly below the right side's.
                if (left.count && right.count) {
                    EXPECT_LT(left.centers.max[a], right.centers.min[a]) << "node " << n;
                }
            }
        }
}

TEST(BihBuild, SplitPlanesComeFromTheGlobalCandidateBox) {
    // Two clusters at opposite corners of [0, 1024]^3: the first candidate plane is x = 512 (the
    // middle of the scene's box, whatever the objects' own distribution), so the root's planes
    // separate the clusters on x, and the cut mode then trims each child's empty space.
    TriangleMesh m;
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(1.0f, 7.0f);
    for (int i = 0; i < 200; ++i) {
        const Vec3 base = i % 2 ? Vec3(1016.0f) : Vec3(0.0f);
        const Vec3 p = base + Vec3(u(rng), u(rng), u(rng));
        add_triangle(m, p, p + Vec3(0.1f, 0, 0), p + Vec3(0, 0.1f, 0));
    }
    add_triangle(m, {0, 0, 0}, {0.1f, 0, 0}, {0, 0.1f, 0});
    add_triangle(m, {1024, 1024, 1024}, {1023.9f, 1024, 1024}, {1024, 1023.9f, 1024});
    Scene scene;
    scene.mesh = m;
    const auto cut = make_bih(scene, 4, BihEmptySide::Cut), refine = make_bih(scene, 4, BihEmptySide::Refine);
    for (const auto* bih : {&cut, &refine}) {
        const BihNode& root = bih->data().nodes[0];
        ASSERT_FALSE(root.is_leaf());
        EXPECT_EQ(root.axis(), 0);
        EXPECT_LE(root.left_max(), 8.2f);
        EXPECT_GE(root.right_min(), 1015.9f);
    }
    EXPECT_EQ(bih_figures(refine.data()).empty_leaves, 0u) << "refine makes no node for an empty side";
    EXPECT_GT(bih_figures(cut.data()).empty_leaves, 0u);
    EXPECT_LT(bih_figures(cut.data()).sah_cost, bih_figures(refine.data()).sah_cost)
        << "cutting off the clusters' empty space tightens the implicit boxes";
}

TEST(BihBuild, InseparableCentresAreSplitByCount) {
    // Every box centre equal: no plane separates them; halving by count keeps leaves small and
    // the depth logarithmic.
    TriangleMesh m;
    for (int i = 0; i < 1000; ++i) {
        const float s = 1.0f + float(i % 37);
        add_triangle(m, {-s, -s, 0}, {s, -s, 0}, {-s, s, 0});
        add_triangle(m, {s, s, 0}, {-s, s, 0}, {s, -s, 0});
    }
    Scene scene;
    scene.mesh = m;
    const auto bih = make_bih(scene, 2);
    const BihFigures f = bih_figures(bih.data());
    EXPECT_LE(f.max_leaf_size, 2u);
    EXPECT_LE(f.max_depth, 12u);
    BruteForce<Triangles<>> brute{Triangles<>(m)};
    const testing::PrimitiveProbe probe(scene, "moller");
    for (float x : {-40.0f, -3.0f, 0.0f, 0.5f, 20.0f}) {
        const Ray ray{{x, 0.25f, 5.0f}, 0.0f, {0.0f, -0.0f, -1.0f}, kInfinity};
        EXPECT_TRUE(testing::same_closest_hit(bih.intersect(ray), brute.intersect(ray), ray, probe)) << x;
    }
}

TEST(BihBuild, SahCostLiesBetweenOneLeafAndTheSahBvh) {
    // The lecture's table rates the BIH "medium": its SAH cost lies between a single leaf's and
    // the binned-SAH BVH's (both with the same constants).
    const Scene scene = soup();
    const double bih = bih_figures(make_bih(scene, 4).data()).sah_cost;
    const Bvh<Triangles<>> bvh(Triangles<>(scene.mesh), BvhBuildOptions{});
    EXPECT_LT(bih, double(scene.primitive_count()));
    EXPECT_GT(bih, bvh_figures(bvh.data()).sah_cost);
}

TEST(BihTraversal, FarChildIsSkippedOnceAHitIsCloser) {
    // A wall in front of a dense block, far apart on z: the root splits them, and the block's
    // subtree is entered after the wall's hit only if the traversal ignores the early-out.
    TriangleMesh m;
    add_triangle(m, {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1});
    add_triangle(m, {1, 1, 1}, {-1, 1, 1}, {1, -1, 1});
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-1.0f, 0.8f);
    for (int i = 0; i < 500; ++i) {
        const Vec3 p(u(rng), u(rng), 20.0f + u(rng));
        add_triangle(m, p, p + Vec3(0.2f, 0, 0), p + Vec3(0, 0.2f, 0));
    }
    Scene scene;
    scene.mesh = m;
    const auto bih = make_bih(scene, 4);
    RayCounters c;
    const Hit hit = bih.closest(Ray{{0.1f, 0.2f, -5.0f}, 0.0f, {0, 0, 1}, kInfinity}, c);
    ASSERT_TRUE(hit.found());
    EXPECT_LT(hit.prim, 2u);
    EXPECT_EQ(c.prims, 2u) << "only the wall's leaf is tested";
    EXPECT_LE(c.nodes, 3u);
}

TEST(BihTraversal, AgreesWithBruteForceOnAxisParallelRaysThroughPlanes) {
    // Rays along the axes lying exactly on clip planes (vertex coordinates), with +0 and -0.
    const Scene scene = testing::nasty_scenes()[8];  // the closed cube
    ASSERT_EQ(scene.name, "closed-cube");
    const auto bih = make_bih(scene, 1);
    BruteForce<Triangles<>> brute{Triangles<>(scene.mesh)};
    const testing::PrimitiveProbe probe(scene, "moller");
    int rays = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (float s : {1.0f, -1.0f})
            for (float zero : {0.0f, -0.0f})
                for (int i = 0; i <= 6; ++i)
                    for (int j = 0; j <= 6; ++j) {
                        Vec3 o, d(zero);
                        o[axis] = s > 0 ? -1.0f : 2.0f;
                        o[(axis + 1) % 3] = float(i) / 6.0f;
                        o[(axis + 2) % 3] = float(j) / 6.0f;
                        d[axis] = s;
                        const Ray ray{o, 0.0f, d, kInfinity};
                        ASSERT_TRUE(testing::same_closest_hit(bih.intersect(ray), brute.intersect(ray), ray, probe))
                            << "axis " << axis << " i " << i << " j " << j;
                        ASSERT_EQ(bih.occluded(ray), brute.occluded(ray));
                        ++rays;
                    }
    EXPECT_EQ(rays, 3 * 2 * 2 * 49);
}

TEST(BihIo, RoundTripAndCorruptPayloads) {
    const Scene scene = soup();
    const auto bih = make_bih(scene, 4);
    std::ostringstream out;
    write_bih(out, bih.data());
    const std::string payload = out.str();
    std::istringstream in(payload);
    const BihData back = read_bih(in, scene.primitive_count());
    EXPECT_EQ(back.nodes.size(), bih.data().nodes.size());
    EXPECT_EQ(back.prim_indices, bih.data().prim_indices);

    std::istringstream truncated(payload.substr(0, payload.size() / 2));
    EXPECT_THROW(read_bih(truncated, scene.primitive_count()), Error);
    std::istringstream other_scene(payload);
    EXPECT_THROW(read_bih(other_scene, scene.primitive_count() + 1), Error);
    // A leaf pointing past the index array.
    BihData broken = bih.data();
    for (BihNode& node : broken.nodes)
        if (node.is_leaf() && node.count() > 0) {
            node = BihNode::leaf(uint32_t(scene.primitive_count()), node.count());
            break;
        }
    EXPECT_THROW(validate_bih(broken, scene.primitive_count()), Error);
    // A cycle: a child pointing back at the root.
    broken = bih.data();
    broken.nodes[0] = BihNode::inner(0, 0, 1.0f, 0.0f);
    EXPECT_THROW(validate_bih(broken, scene.primitive_count()), Error);
}

TEST(BihSpec, OptionsAreChecked) {
    EXPECT_THROW(parse_accel_spec("bih:max-leaf=0"), Error);
    EXPECT_THROW(parse_accel_spec("bih:empty=sometimes"), Error);
    EXPECT_EQ(parse_accel_spec("bih").str(), "bih:empty=cut,isect=moller,max-leaf=4");
}

}  // namespace
}  // namespace thicket::bih_test
