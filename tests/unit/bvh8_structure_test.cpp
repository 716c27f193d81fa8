// bvh8's tree and options: the collapse keeps every triangle exactly once in 4-lane blocks, nodes
// are 256-byte and cache aligned, children follow parents, the ISA choice obeys `isa=` and
// THICKET_ISA, and the statistics report what was built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh8/bvh8.h"
#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"

namespace thicket::bvh8_structure_test {
namespace {

Scene soup() { return testing::nasty_scenes().back(); }

std::string extra(const AccelStats& s, const std::string& key) {
    for (const auto& [k, v] : s.extra)
        if (k == key) return v;
    return "";
}

/// Sets THICKET_ISA for one scope.
class ScopedIsaEnv {
public:
    explicit ScopedIsaEnv(const char* value) {
        const char* old = std::getenv("THICKET_ISA");
        had_ = old != nullptr;
        if (had_) old_ = old;
        if (value)
            ::setenv("THICKET_ISA", value, 1);
        else
            ::unsetenv("THICKET_ISA");
    }
    ~ScopedIsaEnv() {
        if (had_)
            ::setenv("THICKET_ISA", old_.c_str(), 1);
        else
            ::unsetenv("THICKET_ISA");
    }

private:
    bool had_ = false;
    std::string old_;
};

TEST(Bvh8Tree, EveryTriangleIsInExactlyOneBlockLaneDegenerateOnesToo) {
    Scene scene = soup();
    // Append a degenerate (collinear) triangle: it is kept in a lane like every other (closest
    // points reach it, a refit may give it an interior), and counted as a degenerate lane.
    const uint32_t base = uint32_t(scene.mesh.positions.size());
    scene.mesh.positions.insert(scene.mesh.positions.end(), {Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)});
    scene.mesh.indices.insert(scene.mesh.indices.end(), {base, base + 1, base + 2});

    for (int max_leaf : {1, 4, 7}) {
        Bvh8Options o;
        o.binary.max_leaf = max_leaf;
        const Bvh8<Triangles<>> bvh(Triangles<>(scene.mesh), o);
        std::vector<int> seen(scene.mesh.triangle_count(), 0);
        const bvh8::Tree& tree = bvh.tree();
        ASSERT_FALSE(tree.nodes.empty());
        EXPECT_EQ(reinterpret_cast<uintptr_t>(tree.nodes.data()) % 64, 0u);
        std::vector<int> stored(scene.mesh.triangle_count(), 0);
        size_t lanes = 0;
        for (size_t n = 0; n < tree.nodes.size(); ++n) {
            const bvh8::Node& node = tree.nodes[n];
            EXPECT_NE(node.valid, 0u) << "node " << n << " has no child";
            for (int lane = 0; lane < 8; ++lane) {
                if (!((node.valid >> lane) & 1) || node.leaf_size[lane] == 0) continue;
                EXPECT_LE(node.leaf_size[lane], uint32_t((max_leaf + 3) / 4)) << "blocks per leaf";
                for (uint32_t b = 0; b < node.leaf_size[lane]; ++b)
                    for (uint32_t id : bvh.blocks()[node.child[lane] + b].id)
                        if (id != kNoPrim) ++stored[id];
                ++lanes;
            }
        }
        EXPECT_EQ(lanes, tree.leaves);
        for (uint32_t i = 0; i < stored.size(); ++i)
            EXPECT_EQ(stored[i], 1) << "triangle " << i << ", max-leaf " << max_leaf;
        const AccelStats s = bvh.stats();
        EXPECT_EQ(s.primitive_bytes, bvh.blocks().size() * sizeof(bvh8::Tri4));
        EXPECT_EQ(extra(s, "degenerate lanes"), "1") << "max-leaf " << max_leaf;
        EXPECT_EQ(s.primitives, scene.primitive_count());
    }
}

/// Slivers thinner than the degenerate test (sine 5e-8), which Moller-Trumbore still reports
/// hits on, over a floor: every ISA's closest hit, any hit and all hits reject them as brute
/// force does (Triangles::plausible), on single rays and packets alike.
TEST(Bvh8Tree, DegenerateLanesHitsAreRejectedByEveryKernel) {
    Scene scene;
    scene.name = "slivers-over-a-floor";
    TriangleMesh m;
    for (int k = 0; k < 16; ++k) {  // slivers along x at y = 0 (where 1e-7 is exact enough), heights 1 + k/16
        const float x = 3.0f * float(k), z = 1.0f + float(k) / 16.0f;
        const uint32_t b = uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {Vec3(x, 0, z), Vec3(x + 1, 0, z), Vec3(x + 2, 1e-7f, z)});
        m.indices.insert(m.indices.end(), {b, b + 1, b + 2});
    }
    const uint32_t floor = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {Vec3(-1, -1, 0), Vec3(100, -1, 0), Vec3(-1, 100, 0)});
    m.indices.insert(m.indices.end(), {floor, floor + 1, floor + 2});
    scene.add_mesh(m);
    const std::unique_ptr<Accel> brute = build_accel("brute", scene);
    // Straight down through each sliver's interior 1.5 along it (where it spans y 0.5e-7 to 0.75e-7).
    std::vector<Ray> rays;
    for (int k = 0; k < 16; ++k)
        for (int j = 0; j < 4; ++j)
            rays.push_back(Ray{Vec3(3.0f * float(k) + 1.5f + float(j) * 0.05f, 0.6e-7f + float(j) * 0.01e-7f, 3.0f),
                               0.0f, Vec3(0.0f, 0.0f, -1.0f), kInfinity});
    size_t moller_hits = 0;
    for (const Ray& r : rays)
        for (uint32_t i = 0; i + 1 < scene.mesh.triangle_count(); ++i) {
            TriangleHit th;
            moller_hits += intersect_moller(scene.mesh.vertex(i, 0), scene.mesh.vertex(i, 1), scene.mesh.vertex(i, 2), r,
                                            r.tmax, th) ? 1 : 0;
        }
    ASSERT_GT(moller_hits, rays.size() / 2) << "the slivers must be hit by the raw test for this to prove anything";
    for (Isa isa : cpu_isas())
        for (const std::string test : {"moller", "watertight"}) {
            const std::string spec = std::string("bvh8:isa=") + isa_name(isa) + ",isect=" + test;
            const std::unique_ptr<Accel> bvh = build_accel(spec, scene);
            EXPECT_EQ(extra(bvh->stats(), "degenerate lanes"), "16") << spec;
            std::vector<Hit> batch(rays.size());
            BatchOptions coherent;
            coherent.coherent = true;
            bvh->intersect(rays, batch, coherent);
            for (size_t r = 0; r < rays.size(); ++r) {
                const Hit want = brute->intersect(rays[r]);
                ASSERT_EQ(want.prim, floor / 3) << "brute force hits the floor";
                EXPECT_EQ(bvh->intersect(rays[r]).prim, want.prim) << spec << " ray " << r;
                EXPECT_EQ(batch[r].prim, want.prim) << spec << " packet ray " << r;
                Ray shadow = rays[r];
                shadow.tmax = 2.5f;  // ends above the floor: only a sliver could occlude it
                EXPECT_FALSE(bvh->occluded(shadow)) << spec << " ray " << r;
                std::vector<Hit> all;
                bvh->all_hits(rays[r], all);
                ASSERT_EQ(all.size(), 1u) << spec << " ray " << r;
            }
        }
}

TEST(Bvh8Tree, NodesHoldAtMostEightChildrenAfterTheirParent) {
    const Scene scene = soup();
    const Bvh8<Triangles<>> bvh(Triangles<>(scene.mesh), Bvh8Options{});
    const bvh8::Tree& tree = bvh.tree();
    size_t children = 0, full = 0;
    for (size_t n = 0; n < tree.nodes.size(); ++n) {
        const bvh8::Node& node = tree.nodes[n];
        for (int lane = 0; lane < 8; ++lane) {
            if (!((node.valid >> lane) & 1)) continue;
            ++children;
            if (node.leaf_size[lane] == 0) {
                EXPECT_GT(node.child[lane], n) << "depth-first: children after parents";
            }
        }
        full += node.valid == 0xffu;
    }
    EXPECT_EQ(children, tree.nodes.size() - 1 + tree.leaves) << "every node but the root is one lane";
    // The greedy collapse fills a node unless its subtree has fewer than 8 leaves (subtrees of at
    // most 4 triangles are one leaf): the root is full, and a node has 3 or more children on average.
    EXPECT_GE(children, 3 * tree.nodes.size());
    EXPECT_EQ(tree.nodes[0].valid, 0xffu);
    EXPECT_GT(full, 0u);
}

TEST(Bvh8Tree, MixedScenesKeepPrimitiveIdsInLeaves) {
    const Scene scene = testing::mixed_scene();
    auto accel = build_accel("bvh8", scene);
    const AccelStats s = accel->stats();
    EXPECT_EQ(s.primitives, scene.primitive_count());
    EXPECT_EQ(s.bytes, std::stoul(extra(s, "8-wide nodes")) * sizeof(bvh8::Node) +
                           scene.primitive_count() * sizeof(uint32_t))
        << "nodes plus one id per primitive";
    EXPECT_EQ(extra(s, "4-triangle blocks"), "") << "no blocks without the triangle fast path";
}

// Saving keeps the tree as built, for triangle blocks and for the id leaves of mixed scenes:
// the loaded structure reports the same figures and answers bit for bit the same.
TEST(Bvh8Tree, SavedAndLoadedTreesAnswerAndReportAsBuilt) {
    for (const Scene& scene : {testing::mixed_scene(), load_scene("teapot-patches"), load_scene("cornell")}) {
        for (const char* spec : {"bvh8", "bvh8:isect=watertight,leaf-merge=8", "bvh8:quality=high,budget=1"}) {
            auto built = build_accel(spec, scene);
            auto loaded = load_accel_bytes(saved_accel_bytes(*built, scene), scene, "saved.bin");
            const AccelStats a = built->stats(), b = loaded->stats();
            EXPECT_EQ(a.nodes, b.nodes) << spec << " on " << scene.name;
            EXPECT_EQ(a.leaves, b.leaves) << spec << " on " << scene.name;
            EXPECT_EQ(a.max_depth, b.max_depth) << spec << " on " << scene.name;
            EXPECT_EQ(a.bytes, b.bytes) << spec << " on " << scene.name;
            EXPECT_EQ(a.primitive_bytes, b.primitive_bytes) << spec << " on " << scene.name;
            EXPECT_EQ(a.sah_cost, b.sah_cost) << spec << " on " << scene.name;
            EXPECT_EQ(extra(a, "4-triangle blocks"), extra(b, "4-triangle blocks")) << spec << " on " << scene.name;
            EXPECT_EQ(loaded->bounds().min, built->bounds().min);
            EXPECT_EQ(loaded->bounds().max, built->bounds().max);
            for (const Ray& r : testing::conformance_rays(scene, 200, 7)) {
                const Hit x = built->intersect(r), y = loaded->intersect(r);
                ASSERT_EQ(x.prim, y.prim) << spec << " on " << scene.name;
                ASSERT_EQ(x.t, y.t) << spec << " on " << scene.name;
                ASSERT_EQ(built->occluded(r), loaded->occluded(r)) << spec << " on " << scene.name;
            }
        }
    }
}

TEST(Bvh8Tree, StatsReportIsaAndBothSahMetrics) {
    const Scene scene = soup();
    auto accel = build_accel("bvh8:isa=sse", scene);
    const AccelStats s = accel->stats();
    EXPECT_EQ(extra(s, "isa"), "sse");
    EXPECT_GT(s.sah_cost, 1.0);
    EXPECT_GT(std::stod(extra(s, "Embree SAH")), 1.0);
    // Embree's metric counts 4-triangle blocks where Thicket's counts triangles: with full
    // blocks of 4 it is the smaller.
    EXPECT_LT(std::stod(extra(s, "Embree SAH")), s.sah_cost);
}

TEST(Bvh8Quality, PresetsBuildTheTreesOfTheSettingsTheyStandFor) {
    const Scene scene = soup();
    auto same_tree = [&](const std::string& preset, const std::string& settings) {
        const AccelStats a = build_accel("bvh8:" + preset, scene)->stats();
        const AccelStats b = build_accel("bvh8:" + settings, scene)->stats();
        EXPECT_EQ(a.nodes, b.nodes) << preset;
        EXPECT_EQ(a.sah_cost, b.sah_cost) << preset;
        EXPECT_EQ(extra(a, "Embree SAH"), extra(b, "Embree SAH")) << preset;
    };
    same_tree("quality=low", "builder=lbvh");
    same_tree("quality=medium", "builder=binned-sah,bins=16");
    same_tree("quality=high", "builder=sbvh,optimize=reinsertion");
    // The presets differ from each other (else the mapping above would prove nothing).
    EXPECT_NE(build_accel("bvh8:quality=low", scene)->stats().sah_cost,
              build_accel("bvh8:quality=high", scene)->stats().sah_cost);
}

TEST(Bvh8Quality, APresetWithItsOwnBuilderOrBinsIsAnErrorNamingBoth) {
    const Scene scene = soup();
    for (const char* spec : {"bvh8:quality=high,builder=midpoint", "bvh8:quality=low,bins=32"}) {
        try {
            build_accel(spec, scene);
            ADD_FAILURE() << spec << " was accepted";
        } catch (const Error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("quality="), std::string::npos) << msg;
            EXPECT_TRUE(msg.find("builder=midpoint") != std::string::npos || msg.find("bins=32") != std::string::npos)
                << msg;
        }
    }
    EXPECT_NO_THROW(build_accel("bvh8:quality=medium,builder=binned-sah,max-leaf=2", scene));
}

TEST(Bvh8Isa, AutoIsTheBestLevelCappedByTheEnvironment) {
    {
        ScopedIsaEnv env(nullptr);
        EXPECT_EQ(resolve_isa("auto", "bvh8"), cpu_best_isa());
    }
    {
        ScopedIsaEnv env("sse");
        EXPECT_EQ(resolve_isa("auto", "bvh8"), Isa::Sse);
        EXPECT_EQ(extra(build_accel("bvh8", soup())->stats(), "isa"), "sse");
        EXPECT_EQ(resolve_isa("scalar", "bvh8"), Isa::Scalar) << "an explicit level ignores the cap";
    }
    {
        ScopedIsaEnv env("scalar");
        EXPECT_EQ(resolve_isa("auto", "bvh8"), Isa::Scalar);
    }
}

TEST(Bvh8Isa, BadLevelsAreErrorsThatSayWhatTheCpuHas) {
    {
        ScopedIsaEnv env("avx9");
        try {
            resolve_isa("auto", "bvh8");
            FAIL() << "THICKET_ISA=avx9 accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("THICKET_ISA=avx9"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(parse_accel_spec("bvh8:isa=neon"), Error);
    if (cpu_best_isa() != Isa::Avx512) {
        try {
            resolve_isa("avx512", "bvh8");
            FAIL() << "isa=avx512 accepted on a CPU without it";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("it has scalar, sse"), std::string::npos) << e.what();
        }
    }
}

TEST(Bvh8Isa, ConformanceVariantsCoverEveryLevelTheCpuRuns) {
    const AccelInfo* info = find_accel("bvh8");
    ASSERT_NE(info, nullptr);
    for (Isa isa : cpu_isas()) {
        const std::string level = std::string("isa=") + isa_name(isa);
        EXPECT_TRUE(std::any_of(info->variants.begin(), info->variants.end(),
                                [&](const std::string& v) { return v == "bvh8:" + level; }))
            << level;
        EXPECT_TRUE(std::any_of(info->variants.begin(), info->variants.end(),
                                [&](const std::string& v) { return v == "bvh8:" + level + ",isect=watertight"; }))
            << level;
    }
}

TEST(Bvh8Query, CountersCountNodesAndEachPrimitiveAtMostOnce) {
    const Scene scene = soup();
    for (Isa isa : cpu_isas()) {
        auto accel = build_accel(std::string("bvh8:isa=") + isa_name(isa), scene);
        const Ray ray{scene.bounds().center() - Vec3(0, 0, 10), 0.0f, {0, 0, 1}, kInfinity};
        RayCounters c;
        const Hit hit = accel->intersect(ray, c);
        EXPECT_TRUE(hit.found());
        EXPECT_GE(c.nodes, 2u) << "the root and at least one leaf";
        EXPECT_GE(c.prims, 1u);
        EXPECT_LE(c.prims, scene.primitive_count());
        EXPECT_EQ(accel->intersect(ray).prim, hit.prim) << "counting does not change the answer";
        RayCounters any;
        EXPECT_TRUE(accel->occluded(ray, any));
        EXPECT_LE(any.prims, c.prims + scene.primitive_count());
    }
}

// The histogram of children entered per interior visit (issue 43's branch count): a ray that
// misses the root's children visits the root alone and enters nothing; any ray's interior visits
// are at most its visits; every ISA counts the same histogram (the same traversal); any hit
// on a ray that hits nothing visits exactly the root plus every child entered (none pruned), as
// long as no visit entered 5 or more.
TEST(Bvh8Query, CountersSayHowManyChildrenEachInteriorVisitEntered) {
    const Scene scene = soup();
    const std::vector<Ray> rays = testing::conformance_rays(scene, 600, 3);
    std::vector<RayCounters> first;
    for (Isa isa : cpu_isas()) {
        SCOPED_TRACE(isa_name(isa));
        auto accel = build_accel(std::string("bvh8:isa=") + isa_name(isa), scene);
        RayCounters away;
        const Ray miss{scene.bounds().max + Vec3(1, 1, 1), 0.0f, {1, 1, 1}, kInfinity};
        EXPECT_FALSE(accel->intersect(miss, away).found());
        EXPECT_EQ(away.nodes, 1u);
        EXPECT_EQ(away.entered[0], 1u);
        size_t exact = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            RayCounters c;
            accel->intersect(rays[i], c);
            uint64_t interior = 0;
            for (uint64_t v : c.entered) interior += v;
            EXPECT_GE(interior, 1u);
            EXPECT_LE(interior, c.nodes);
            RayCounters any;
            if (!accel->occluded(rays[i], any) && any.entered[5] == 0) {
                const uint64_t children = any.entered[1] + 2 * any.entered[2] + 3 * any.entered[3] + 4 * any.entered[4];
                EXPECT_EQ(any.nodes, 1 + children) << "ray " << i;
                ++exact;
            }
            if (first.size() < rays.size()) {
                first.push_back(c);
            } else {
                EXPECT_EQ(std::memcmp(first[i].entered, c.entered, sizeof c.entered), 0) << "ray " << i;
            }
        }
        EXPECT_GT(exact, 10u) << "rays that hit nothing, to check the any-hit count on";
    }
}

TEST(Bvh8Query, EveryIsaAnswersBitwiseLikeTheScalarKernels) {
    // Every kernel reproduces the scalar operations, and the traversal order depends only on
    // the entry distances, so the answers are identical, ray for ray, bit for bit.
    for (const Scene& scene : {soup(), testing::mixed_scene()}) {
        const std::vector<Ray> rays = testing::conformance_rays(scene, 1500, 5);
        auto scalar = build_accel("bvh8:isa=scalar", scene);
        size_t hits = 0;
        for (Isa isa : cpu_isas()) {
            auto accel = build_accel(std::string("bvh8:isa=") + isa_name(isa), scene);
            for (size_t i = 0; i < rays.size(); ++i) {
                const Hit a = scalar->intersect(rays[i]), b = accel->intersect(rays[i]);
                ASSERT_EQ(a.prim, b.prim) << isa_name(isa) << " ray " << i << " of " << scene.name;
                ASSERT_EQ(std::memcmp(&a, &b, sizeof(Hit)), 0) << isa_name(isa) << " ray " << i;
                ASSERT_EQ(scalar->occluded(rays[i]), accel->occluded(rays[i])) << isa_name(isa) << " ray " << i;
                hits += a.found();
            }
        }
        EXPECT_GT(hits, rays.size() / 10) << scene.name;
    }
}

}  // namespace
}  // namespace thicket::bvh8_structure_test

namespace thicket::bvh8_foreign_tree_test {
namespace {

/// A foreign builder for the test: leaves of 3 primitives in index order, grouped 8 (then 5 at
/// the top, to have a node that is not full) bottom-up into nodes whose boxes are their unions.
bvh8::WideTree grouped_tree(const bvh8::ForeignTreeRequest& request) {
    bvh8::WideTree wide;
    std::vector<uint32_t> level;  // item indices of the level being grouped
    std::vector<bvh8::WideTree::Item> items;
    for (uint32_t i = 0; i < request.prim_bounds.size(); i += 3) {
        bvh8::WideTree::Item leaf{{}, i, std::min<uint32_t>(3, uint32_t(request.prim_bounds.size()) - i), true};
        for (uint32_t p = i; p < i + leaf.count; ++p) {
            leaf.box.grow(request.prim_bounds[p]);
            wide.prims.push_back(p);
        }
        level.push_back(uint32_t(items.size()));
        items.push_back(leaf);
    }
    while (level.size() > 1) {
        const size_t group = level.size() <= 5 ? 5 : 8;
        std::vector<uint32_t> next;
        for (size_t i = 0; i < level.size(); i += group) {
            bvh8::WideTree::Item node{{}, uint32_t(wide.children.size()), 0, false};
            for (size_t k = i; k < std::min(level.size(), i + group); ++k) {
                node.box.grow(items[level[k]].box);
                wide.children.push_back(level[k]);
                ++node.count;
            }
            next.push_back(uint32_t(items.size()));
            items.push_back(node);
        }
        level = next;
    }
    // The root first: swap it with item 0 and fix the references.
    const uint32_t root = level.empty() ? 0 : level[0];
    if (!items.empty() && root != 0) {
        std::swap(items[0], items[root]);
        for (uint32_t& c : wide.children) c = c == 0 ? root : c == root ? 0 : c;
    }
    wide.items = std::move(items);
    return wide;
}

/// Uninstalls the test's builder whatever happens.
struct InstalledBuilder {
    explicit InstalledBuilder(bvh8::ForeignTreeBuilder b) { bvh8::set_foreign_tree_builder(b); }
    ~InstalledBuilder() { bvh8::set_foreign_tree_builder(nullptr); }
};

TEST(Bvh8ForeignTree, WithoutABuilderEmbreesTreesAreRefusedNamingTheBench) {
    const Scene scene = load_scene("cornell");
    for (const char* spec : {"bvh8:tree=embree-medium", "bvh8:tree=embree-high"}) {
        try {
            build_accel(spec, scene);
            ADD_FAILURE() << spec << " built without a foreign builder";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("thicket bench"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(std::string(spec).substr(5)), std::string::npos) << e.what();
        }
    }
}

TEST(Bvh8ForeignTree, OurBuildersKeysAreRefusedWithEmbreesTree) {
    const InstalledBuilder installed(&grouped_tree);
    const Scene scene = load_scene("cornell");
    for (const char* spec : {"bvh8:tree=embree-medium,max-leaf=8", "bvh8:tree=embree-high,quality=high",
                             "bvh8:tree=embree-medium,builder=sweep-sah"}) {
        try {
            build_accel(spec, scene);
            ADD_FAILURE() << spec << " built, its builder key unused";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("would do nothing"), std::string::npos) << e.what();
        }
    }
    // The keys that still apply, and a preset that sets only defaults, are taken.
    EXPECT_NO_THROW(build_accel("bvh8:tree=embree-medium,isa=scalar,nodes=compressed,isect=watertight", scene));
    EXPECT_NO_THROW(build_accel("bvh8:tree=embree-medium,quality=medium", scene));
}

TEST(Bvh8ForeignTree, AWideTreeIsWrittenAsItIsAndAnswersLikeBruteForce) {
    const InstalledBuilder installed(&grouped_tree);
    for (const Scene& scene : {load_scene("cornell"), testing::nasty_scenes().back()}) {
        SCOPED_TRACE(scene.name);
        const auto accel = build_accel("bvh8:tree=embree-medium", scene);
        const auto& bvh = dynamic_cast<const Bvh8<Triangles<>>&>(*accel);
        const bvh8::Tree& tree = bvh.tree();
        // One 8-wide node per interior item, in the item's child order: the first node's lanes
        // are the root's children, and the last level's first node holds leaves of 3 primitives.
        const size_t leaves = (scene.primitive_count() + 2) / 3;
        size_t interior = 0;
        for (size_t level = leaves; level > 1;) {
            const size_t group = level <= 5 ? 5 : 8;
            level = (level + group - 1) / group;
            interior += level;
        }
        EXPECT_EQ(tree.nodes.size(), interior);
        const auto brute = build_accel("brute", scene);
        for (const Ray& ray : testing::conformance_rays(scene, 400)) {
            const Hit a = accel->intersect(ray), b = brute->intersect(ray);
            EXPECT_TRUE(a.t == b.t && (a.prim == b.prim || a.found())) << a.prim << " " << b.prim;
            EXPECT_EQ(accel->occluded(ray), brute->occluded(ray));
        }
    }
}

}  // namespace
}  // namespace thicket::bvh8_foreign_tree_test
