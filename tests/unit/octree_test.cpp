#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <sstream>

#include "support/probe.h"
#include "support/reference.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/brute/brute_force.h"
#include "thicket/core/error.h"
#include "thicket/octree/octree.h"
#include "thicket/prims/triangles.h"

namespace thicket::octree_test {
namespace {

Scene soup() { return testing::nasty_scenes().back(); }

Octree<Triangles<>> make_octree(const Scene& scene, OctreeTraversal traversal, int leaf_size = 8, int max_depth = 10) {
    OctreeBuildOptions o;
    o.leaf_size = leaf_size;
    o.max_depth = max_depth;
    return Octree<Triangles<>>(Triangles<>(scene.mesh), o, traversal);
}

void add_triangle(TriangleMesh& m, Vec3 a, Vec3 b, Vec3 c) {
    const auto base = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

/// Every leaf's cell, by node index, derived from the root as the traversals derive them.
std::map<uint32_t, Aabb> leaf_cells(const OctreeData& tree) {
    std::map<uint32_t, Aabb> cells;
    std::vector<std::pair<uint32_t, Aabb>> stack{{0, tree.root}};
    while (!stack.empty()) {
        const auto [n, box] = stack.back();
        stack.pop_back();
        if (tree.nodes[n].is_leaf()) {
            cells[n] = box;
            continue;
        }
        for (int c = 0; c < 8; ++c) stack.push_back({tree.nodes[n].index + uint32_t(c), octree_child_box(box, c)});
    }
    return cells;
}

/// Counters that also record the leaves a query tests, in order.
struct LeafRecorder {
    std::vector<uint32_t> leaves;
    uint64_t nodes = 0, prims = 0;
    void node() { ++nodes; }
    void prim() { ++prims; }
    void leaf(uint32_t n) { leaves.push_back(n); }
};

/// The ray's exact (unwidened) interval through a box, for telling cells it crosses from cells
/// it only touches.
std::pair<float, float> crossing(const Ray& ray, const Aabb& box) {
    const RayBoxQuery q(ray);
    float t0 = -kInfinity, t1 = kInfinity;
    for (int a = 0; a < 3; ++a) {
        const float n = plane_distance(q, a, q.neg[a] ? box.max[a] : box.min[a]);
        const float f = plane_distance(q, a, q.neg[a] ? box.min[a] : box.max[a]);
        t0 = std::max(t0, n);
        t1 = std::min(t1, f);
    }
    return {t0, t1};
}

TEST(OctreeLayout, NodeIsEightBytes) { EXPECT_EQ(sizeof(OctreeNode), 8u); }

TEST(OctreeBuild, LeavesReferenceExactlyThePrimitivesTouchingTheirCell) {
    const Scene scene = soup();
    const auto tree = make_octree(scene, OctreeTraversal::Parametric, 4, 6);
    const OctreeData& d = tree.data();
    const Triangles<>& prims = tree.primitives();
    for (uint32_t i = 0; i < prims.size(); ++i) {
        for (int a = 0; a < 3; ++a) {
            EXPECT_LE(d.root.min[a], prims.bounds(i).min[a]);
            EXPECT_GE(d.root.max[a], prims.bounds(i).max[a]);
        }
    }
    const Vec3 e = d.root.extent();
    EXPECT_EQ(e.x, e.y);
    EXPECT_EQ(e.y, e.z) << "Glassner's cells are cubes";
    size_t leaves = 0;
    for (const auto& [n, box] : leaf_cells(d)) {
        ++leaves;
        const OctreeNode& node = d.nodes[n];
        std::vector<uint8_t> in_leaf(prims.size(), 0);
        for (uint32_t r = node.index; r < node.index + node.count; ++r) {
            if (r > node.index) {
                EXPECT_LT(d.refs[r - 1], d.refs[r]) << "ascending, no duplicates";
            }
            in_leaf[d.refs[r]] = 1;
        }
        for (uint32_t i = 0; i < prims.size(); ++i)
            ASSERT_EQ(in_leaf[i] != 0, !intersection(prims.bounds(i), box).empty() &&
                                           !clipped_bounds(prims, i, box).empty())
                << "primitive " << i << " in leaf " << n << ": referenced iff its clipped part is non-empty";
    }
    EXPECT_GT(leaves, 64u);
}

TEST(OctreeBuild, CellsSplitUntilSmallDeepOrInseparable) {
    const Scene scene = soup();
    for (int leaf_size : {3, 8}) {
        const auto tree = make_octree(scene, OctreeTraversal::Parametric, leaf_size, 7);
        const OctreeData& d = tree.data();
        const OctreeFigures f = octree_figures(d);
        ASSERT_LT(f.references, kOctreeReferenceBudget * scene.primitive_count()) << "the budget stopped nothing";
        EXPECT_EQ(f.nodes, d.nodes.size()) << "every node is reachable";
        EXPECT_EQ(f.references, d.refs.size());
        EXPECT_LE(f.max_depth, 7u);
        EXPECT_GT(f.empty_leaves, 0u);
        for (const auto& [n, box] : leaf_cells(d)) {
            const OctreeNode& node = d.nodes[n];
            if (node.count <= uint32_t(leaf_size)) continue;
            // A big leaf is at max depth, or no octant would have held fewer primitives.
            const int depth = int(std::lround(std::log2(d.root.extent().x / box.extent().x)));
            if (depth >= 7) continue;
            size_t non_empty = 0, full = 0;
            for (int c = 0; c < 8; ++c) {
                size_t count = 0;
                for (uint32_t r = node.index; r < node.index + node.count; ++r)
                    count += !clipped_bounds(tree.primitives(), d.refs[r], octree_child_box(box, c)).empty();
                non_empty += count > 0;
                full += count == node.count;
            }
            EXPECT_TRUE(non_empty >= 2 && full == non_empty) << "leaf " << n << " of " << node.count << " could split";
        }
    }
}

TEST(OctreeBuild, CoincidentGeometryStopsSplitting) {
    // Forty copies of one triangle: no split separates them, so the root stays a leaf.
    TriangleMesh m;
    for (int i = 0; i < 40; ++i) add_triangle(m, {0, 0, 0}, {1, 0.2f, 0}, {0.3f, 1, 0.5f});
    Scene scene;
    scene.mesh = m;
    const auto tree = make_octree(scene, OctreeTraversal::Parametric, 8, 16);
    EXPECT_EQ(octree_figures(tree.data()).nodes, 1u);
    EXPECT_EQ(tree.data().refs.size(), 40u);
}

TEST(OctreeBuild, FlatSceneGetsCubicCellsAndBoundedReferences) {
    // A tessellated floor: zero extent in y. The cells stay cubes (never flat), and the
    // references stay within the budget however deep the tree may go.
    TriangleMesh m;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j) {
            const Vec3 p(float(i), 0, float(j));
            add_triangle(m, p, p + Vec3(1, 0, 0), p + Vec3(1, 0, 1));
            add_triangle(m, p, p + Vec3(1, 0, 1), p + Vec3(0, 0, 1));
        }
    Scene scene;
    scene.mesh = m;
    const auto tree = make_octree(scene, OctreeTraversal::Parametric, 1, 16);
    const OctreeData& d = tree.data();
    EXPECT_GT(d.root.extent().y, 0.0f);
    EXPECT_LE(d.refs.size(), kOctreeReferenceBudget * scene.primitive_count() + 4096);
    BruteForce<Triangles<>> brute{Triangles<>(m)};
    const testing::PrimitiveProbe probe(scene, "moller");
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(0.0f, 64.0f);
    for (int i = 0; i < 500; ++i) {
        // Straight down onto grid lines and vertices (integer coordinates), and slanted.
        const Vec3 o(std::floor(u(rng)) + (i % 3 == 0 ? 0.0f : 0.5f), 10.0f, std::floor(u(rng)));
        const Vec3 dir = i % 2 ? Vec3(-0.0f, -1.0f, 0.0f) : Vec3(0.3f, -1.0f, -0.2f);
        const Ray ray{o, 0.0f, dir, kInfinity};
        EXPECT_TRUE(testing::same_closest_hit(tree.intersect(ray), brute.intersect(ray), ray, probe)) << "ray " << i;
    }
}

TEST(OctreeTraversal, BothTraversalsVisitTheSameLeavesInOrder) {
    const Scene scene = soup();
    const auto parametric = make_octree(scene, OctreeTraversal::Parametric, 4, 8);
    const auto restart = make_octree(scene, OctreeTraversal::Restart, 4, 8);
    const auto cells = leaf_cells(parametric.data());
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    uint64_t parametric_nodes = 0, restart_nodes = 0;
    size_t compared = 0;
    for (int i = 0; i < 2000; ++i) {
        const Ray ray{{u(rng), u(rng), u(rng)}, 0.0f, {u(rng), u(rng), u(rng)}, kInfinity};
        LeafRecorder a, b;
        const Hit ha = parametric.closest(ray, a), hb = restart.closest(ray, b);
        ASSERT_EQ(ha.prim, hb.prim) << "ray " << i;
        ASSERT_EQ(ha.t, hb.t) << "ray " << i;
        EXPECT_EQ(a.prims, b.prims) << "ray " << i << ": the same primitives are tested";
        // Cells the ray only touches (zero length along it) may be taken or not at a tie.
        auto crossed = [&](const std::vector<uint32_t>& leaves) {
            std::vector<uint32_t> out;
            for (uint32_t n : leaves) {
                const auto [t0, t1] = crossing(ray, cells.at(n));
                if (t0 < t1) out.push_back(n);
            }
            return out;
        };
        ASSERT_EQ(crossed(a.leaves), crossed(b.leaves)) << "ray " << i;
        compared += a.leaves.size();
        parametric_nodes += a.nodes;
        restart_nodes += b.nodes;
    }
    EXPECT_GT(compared, 4000u);
    // The restart descends from the root for every leaf; the parametric traversal visits each
    // inner node on the path once.
    EXPECT_LT(parametric_nodes, restart_nodes);
}

TEST(OctreeTraversal, RaysInMidPlanesAndParallelToThem) {
    // Walls crossing the root's mid-planes (the root is [0,4]^3, mid-planes at 2, then 1, 3, ...),
    // hit by rays lying in those planes, along them with +0 and -0 components.
    TriangleMesh m;
    for (int i = 0; i <= 4; ++i) {
        const float x = float(i);
        add_triangle(m, {x, 0, 0}, {x, 4, 0}, {x, 0, 4});
        add_triangle(m, {x, 4, 4}, {x, 0, 4}, {x, 4, 0});
        add_triangle(m, {0, x, 0}, {4, x, 0}, {0, x, 4});
    }
    Scene scene;
    scene.mesh = m;
    BruteForce<Triangles<>> brute{Triangles<>(m)};
    const testing::PrimitiveProbe probe(scene, "moller");
    for (auto traversal : {OctreeTraversal::Parametric, OctreeTraversal::Restart}) {
        const auto tree = make_octree(scene, traversal, 1, 5);
        ASSERT_EQ(tree.data().root.max.x, 4.0f);
        int rays = 0;
        for (float y : {1.0f, 2.0f, 2.5f, 3.0f})
            for (float z : {0.0f, 1.0f, 2.0f, 3.5f, 4.0f})
                for (float s : {1.0f, -1.0f})
                    for (float zero : {0.0f, -0.0f}) {
                        const Vec3 o(s > 0 ? -1.0f : 5.0f, y, z);
                        for (const Vec3 dir : {Vec3(s, zero, zero), Vec3(s, zero, 0.25f), Vec3(s, 0.5f, zero)}) {
                            const Ray ray{o, 0.0f, dir, kInfinity};
                            ASSERT_TRUE(testing::same_closest_hit(tree.intersect(ray), brute.intersect(ray), ray, probe))
                                << "y " << y << " z " << z << " dir " << dir.x << "," << dir.y << "," << dir.z;
                            ASSERT_EQ(tree.occluded(ray), brute.occluded(ray));
                            ++rays;
                        }
                    }
        EXPECT_EQ(rays, 240);
    }
}

TEST(OctreeTraversal, MailboxTestsAPrimitiveOncePerQuery) {
    // One big triangle spans every cell; a small one in each of many cells keeps them split.
    TriangleMesh m;
    add_triangle(m, {0, 0, 0.5f}, {8, 0, 0.5f}, {0, 8, 0.5f});
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            const Vec3 p(float(i) + 0.25f, float(j) + 0.25f, 8.0f * float((i + j) % 2));
            add_triangle(m, p, p + Vec3(0.1f, 0, 0), p + Vec3(0, 0.1f, 0));
        }
    Scene scene;
    scene.mesh = m;
    for (auto traversal : {OctreeTraversal::Parametric, OctreeTraversal::Restart}) {
        const auto tree = make_octree(scene, traversal, 1, 4);
        // Along the big triangle's plane, just above it: every cell crossed references it.
        const Ray ray{{-1, 0.01f, 0.5001f}, 0.0f, {1, 0.0f, 0.0f}, kInfinity};
        LeafRecorder rec;
        tree.closest(ray, rec);
        EXPECT_GT(rec.leaves.size(), 3u);
        EXPECT_EQ(rec.prims, 1u) << "the big triangle is tested once however many cells hold it";
    }
}

TEST(OctreeSpec, OptionsAreChecked) {
    EXPECT_THROW(parse_accel_spec("octree:max-depth=17"), Error);
    EXPECT_THROW(parse_accel_spec("octree:leaf-size=0"), Error);
    EXPECT_THROW(parse_accel_spec("octree:traversal=ropes"), Error);
    OctreeBuildOptions bad;
    bad.max_depth = 40;
    EXPECT_THROW(build_octree({}, {}, bad), Error);
}

// validate_octree names each structural defect of a tree edited in memory.
TEST(OctreeSave, StructuralDefectsAreNamed) {
    const Scene scene = soup();
    auto accel = build_accel("octree:leaf-size=2", scene);
    const OctreeData& built = dynamic_cast<const Octree<Triangles<>>&>(*accel).data();
    ASSERT_FALSE(built.nodes[0].is_leaf());
    std::ostringstream out;
    accel->save(out);
    std::istringstream in(out.str());
    const OctreeData back = read_octree(in, scene.primitive_count());
    EXPECT_EQ(back.refs, built.refs);
    EXPECT_EQ(back.nodes.size(), built.nodes.size());
    auto broken = [&](auto edit, const std::string& needle) {
        OctreeData d = built;
        edit(d);
        try {
            validate_octree(d, scene.primitive_count());
            ADD_FAILURE() << "validate_octree accepted: " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    broken([](OctreeData& d) { d.nodes[0].index = 0; }, "children out of range");
    broken([](OctreeData& d) { d.nodes[0].index = uint32_t(d.nodes.size() - 7); }, "children out of range");
    broken([](OctreeData& d) { d.refs[0] = 1u << 30; }, "reference to primitive");
    broken([](OctreeData& d) { d.nodes.emplace_back(); }, "unreachable");
    broken([](OctreeData& d) {
        for (OctreeNode& n : d.nodes)
            if (n.is_leaf()) n.count = uint32_t(d.refs.size()) + 1;
    }, "references out of range");
}

TEST(OctreeSpec, EmptySceneHasNoNodesAndMissesEverything) {
    const Scene scene;
    for (const char* spec : {"octree", "octree:traversal=restart"}) {
        auto accel = build_accel(spec, scene);
        EXPECT_EQ(accel->stats().nodes, 0u);
        EXPECT_TRUE(accel->bounds().empty());
        EXPECT_FALSE(accel->intersect({{0, 0, 0}, 0.0f, {1, 0, 0}, kInfinity}).found());
        EXPECT_FALSE(accel->occluded({{0, 0, 0}, 0.0f, {1, 0, 0}, kInfinity}));
    }
}

}  // namespace
}  // namespace thicket::octree_test
