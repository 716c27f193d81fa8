// The traversal recorder (core/traversal_record.h) held to an independent expectation: the nodes
// and cells a recorded ray reports are checked against a brute-force slab test in double over
// every node or cell of the structure, the primitives against the leaves' lists, and the totals
// against the plain counting path.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "support/independent_math.h"
#include "thicket/accel/registry.h"
#include "thicket/brute/brute_force.h"
#include "thicket/bvh/bvh.h"
#include "thicket/grid/grid.h"
#include "thicket/prims/triangles.h"

namespace thicket::traversal_record_test {
namespace {

/// 300 random small triangles in the unit cube (a soup with many overlapping boxes).
Scene soup() {
    std::mt19937 rng(29);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), d(-0.08f, 0.08f);
    Scene s;
    s.name = "soup";
    for (uint32_t t = 0; t < 300; ++t) {
        const Vec3 c{u(rng), u(rng), u(rng)};
        for (int k = 0; k < 3; ++k) s.mesh.positions.push_back(c + Vec3{d(rng), d(rng), d(rng)});
        s.mesh.indices.insert(s.mesh.indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    }
    return s;
}


std::vector<Ray> rays() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    std::vector<Ray> out;
    for (int i = 0; i < 200; ++i) {
        Ray r;
        r.org = {u(rng), u(rng), -1.0f};
        r.dir = Vec3{u(rng), u(rng), 3.0f} - r.org;
        out.push_back(r);
    }
    return out;
}

// Margin in t (the rays are ~3 long, boxes ~0.1 to 1): crossings this close to a decision are
// left out of the exact comparison, as float and double may decide them differently.
constexpr double kMargin = 1e-4;

TEST(TraversalRecord, BvhEntersExactlyTheBoxesCrossedBeforeTheHit) {
    const Scene scene = soup();
    const std::unique_ptr<Accel> accel = build_accel("bvh", scene, 1);
    const BruteForce<Triangles<>> brute{Triangles<>(scene.mesh)};
    std::vector<DrawnNode> nodes;
    ASSERT_TRUE(accel->for_each_node([&](const DrawnNode& n) { nodes.push_back(n); }));
    std::map<uint32_t, DrawnNode> by_id;
    for (const DrawnNode& n : nodes) by_id[n.id] = n;
    const auto& bvh = static_cast<const Bvh<Triangles<>>&>(*accel).data();
    size_t compared = 0, hits = 0;
    for (Ray ray : rays()) {
        // Traced with tmax at the closest hit: every box test then sees the final far end, so the
        // entered set is exactly the boxes crossed before the hit.
        NoCounters none;
        const Hit truth = brute.closest(ray, none);
        hits += truth.found();
        ray.tmax = truth.found() ? truth.t : kInfinity;
        TraversalRecorder rec;
        const Hit hit = accel->intersect(ray, rec);
        ASSERT_TRUE(rec.detailed);
        EXPECT_EQ(hit.prim, truth.prim);
        std::set<uint32_t> entered, culled;
        EXPECT_TRUE(std::none_of(rec.steps.begin(), rec.steps.end(),
                                 [](const TraversalStep& s) { return s.kind == TraversalStep::Kind::Skip; }))
            << "with tmax at the hit no deferred node can be beyond it";
        std::vector<uint32_t> leaf_prims, tested;
        for (const TraversalStep& s : rec.steps) {
            if (s.kind == TraversalStep::Kind::Prim) {
                tested.push_back(s.id);
                continue;
            }
            ASSERT_TRUE(by_id.count(s.id)) << "step names node " << s.id << ", not a node of the tree";
            (s.kind == TraversalStep::Kind::Enter ? entered : culled).insert(s.id);
            if (s.kind == TraversalStep::Kind::Enter && by_id[s.id].leaf) {
                const BvhNode& leaf = bvh.nodes[s.id];
                for (uint32_t i = leaf.leftFirst; i < leaf.leftFirst + leaf.count; ++i)
                    leaf_prims.push_back(bvh.prim_indices[i]);
            }
        }
        for (const DrawnNode& n : nodes) {
            const auto [t_in, t_out] = testing::slab_double(ray, n.box);
            const double end = std::min(t_out, double(ray.tmax));
            const bool crossed = t_in <= end - kMargin;
            const bool missed = t_in > end + kMargin;
            if (crossed) {
                EXPECT_TRUE(entered.count(n.id)) << "node " << n.id << " crossed at " << t_in << " not entered";
            }
            if (missed) {
                EXPECT_FALSE(entered.count(n.id)) << "node " << n.id << " missed but entered";
            }
            compared += crossed || missed;
        }
        // The primitives tested are exactly the entered leaves' (in the order the leaves are
        // processed, which for deferred far children is not the order they were entered).
        std::sort(tested.begin(), tested.end());
        std::sort(leaf_prims.begin(), leaf_prims.end());
        EXPECT_EQ(tested, leaf_prims);
        // The steps and the totals are one count; the totals those of the plain counting path.
        RayCounters plain;
        accel->intersect(ray, plain);
        EXPECT_EQ(rec.nodes, entered.size() + culled.size());
        EXPECT_EQ(rec.prims, tested.size());
        EXPECT_EQ(plain.nodes, rec.nodes);
        EXPECT_EQ(plain.prims, rec.prims);
    }
    EXPECT_GT(hits, 50u);
    EXPECT_GT(compared, 200u * nodes.size() * 99 / 100);
}

TEST(TraversalRecord, GridWalksExactlyTheCellsCrossedBeforeTheHitsCell) {
    const Scene scene = soup();
    const std::unique_ptr<Accel> accel = build_accel("grid", scene, 1);
    const BruteForce<Triangles<>> brute{Triangles<>(scene.mesh)};
    const GridFrame& f = static_cast<const Grid<Triangles<>>&>(*accel).data().frame;
    size_t checked = 0;
    for (Ray ray : rays()) {
        NoCounters none;
        const Hit truth = brute.closest(ray, none);
        TraversalRecorder rec;
        const Hit hit = accel->intersect(ray, rec);
        ASSERT_TRUE(rec.detailed);
        EXPECT_EQ(hit.prim, truth.prim);
        std::vector<std::pair<uint32_t, float>> walked;
        for (const TraversalStep& s : rec.steps) {
            if (s.kind == TraversalStep::Kind::Enter) {
                walked.emplace_back(s.id, s.t);
            } else {
                ASSERT_EQ(s.kind, TraversalStep::Kind::Prim) << "a grid culls no cell";
            }
        }
        // The walk ends in the cell where the hit lies (or where the ray leaves the grid): every
        // cell crossed before the last walked cell's entry is walked, in order of entry, with the
        // entry distance of the double slab test; no cell the ray misses is.
        const double t_last = walked.empty() ? -1.0 : walked.back().second;
        std::map<uint32_t, double> expected;  // cell -> entry
        for (uint32_t z = 0; z < f.res[2]; ++z)
            for (uint32_t y = 0; y < f.res[1]; ++y)
                for (uint32_t x = 0; x < f.res[0]; ++x) {
                    const auto [t_in, t_out] = testing::slab_double(ray, f.cell_box(x, y, z));
                    const uint32_t id = f.index(x, y, z);
                    const bool walked_it = std::any_of(walked.begin(), walked.end(), [&](auto& w) { return w.first == id; });
                    if (t_in < t_out - kMargin && t_in < t_last - kMargin) {
                        EXPECT_TRUE(walked_it) << "cell " << id << " crossed at " << t_in << " before the walk's end " << t_last;
                        expected[id] = t_in;
                        ++checked;
                    }
                    if (t_in > t_out + kMargin) {
                        EXPECT_FALSE(walked_it) << "cell " << id << " missed but walked";
                    }
                }
        for (size_t i = 0; i < walked.size(); ++i) {
            if (i) {
                EXPECT_GE(walked[i].second, walked[i - 1].second) << "cells out of order";
            }
            if (expected.count(walked[i].first)) {
                EXPECT_NEAR(walked[i].second, expected[walked[i].first], 1e-4) << "entry of cell " << walked[i].first;
            }
        }
        RayCounters plain;
        accel->intersect(ray, plain);
        EXPECT_EQ(plain.nodes, walked.size());
        EXPECT_EQ(plain.nodes, rec.nodes);
        EXPECT_EQ(plain.prims, rec.prims);
    }
    EXPECT_GT(checked, 1000u);
}

// With the ray's own tmax the far end comes closer as hits are found: a node entered and deferred
// is then dropped unvisited (the early out); each drop names a node entered before, whose entry
// lies beyond the final hit.
TEST(TraversalRecord, BvhSkipsOnlyDeferredNodesBeyondTheHit) {
    const Scene scene = soup();
    const std::unique_ptr<Accel> accel = build_accel("bvh", scene, 1);
    size_t skips = 0;
    for (const Ray& ray : rays()) {
        TraversalRecorder rec;
        const Hit hit = accel->intersect(ray, rec);
        std::set<uint32_t> entered;
        for (const TraversalStep& s : rec.steps) {
            if (s.kind == TraversalStep::Kind::Enter) entered.insert(s.id);
            if (s.kind != TraversalStep::Kind::Skip) continue;
            ++skips;
            EXPECT_TRUE(entered.count(s.id)) << "node " << s.id << " skipped but never entered";
            EXPECT_GT(s.t, hit.t) << "node " << s.id << " skipped though it starts before the hit";
        }
    }
    EXPECT_GT(skips, 20u);  // the soup is deep enough for the early out to happen
}

TEST(TraversalRecord, StepsBeyondTheLimitAreCountedNotKept) {
    const Scene scene = soup();
    const std::unique_ptr<Accel> accel = build_accel("bvh", scene, 1);
    Ray ray;
    ray.org = {0.5f, 0.5f, -1.0f};
    ray.dir = {0.0f, 0.0f, 1.0f};
    TraversalRecorder all, few;
    few.limit = 3;
    accel->intersect(ray, all);
    accel->intersect(ray, few);
    ASSERT_GT(all.steps.size(), 3u);
    EXPECT_EQ(few.steps.size(), 3u);
    EXPECT_EQ(few.dropped, all.steps.size() - 3);
    EXPECT_TRUE(std::equal(few.steps.begin(), few.steps.end(), all.steps.begin(),
                           [](const TraversalStep& a, const TraversalStep& b) { return a.id == b.id && a.kind == b.kind; }));
}

TEST(TraversalRecord, StructuresThatRecordNoStepsGiveTheTotals) {
    const Scene scene = soup();
    const std::unique_ptr<Accel> accel = build_accel("kdtree", scene, 1);
    Ray ray;
    ray.org = {0.5f, 0.5f, -1.0f};
    ray.dir = {0.0f, 0.0f, 1.0f};
    TraversalRecorder rec;
    RayCounters plain;
    EXPECT_EQ(accel->intersect(ray, rec).prim, accel->intersect(ray, plain).prim);
    EXPECT_FALSE(rec.detailed);
    EXPECT_TRUE(rec.steps.empty());
    EXPECT_EQ(rec.nodes, plain.nodes);
    TraversalRecorder any_rec;
    RayCounters any_plain;
    EXPECT_EQ(accel->occluded(ray, any_rec), accel->occluded(ray, any_plain));
    EXPECT_FALSE(any_rec.detailed);
    EXPECT_TRUE(any_rec.steps.empty());
    EXPECT_EQ(any_rec.nodes, any_plain.nodes);
    // Brute force has no nodes to draw, and says so.
    const std::unique_ptr<Accel> brute = build_accel("brute", scene, 1);
    EXPECT_FALSE(brute->for_each_node([](const DrawnNode&) { ADD_FAILURE() << "brute force drew a node"; }));
    EXPECT_FALSE(brute->drawing_legend().has_value());
}

}  // namespace
}  // namespace thicket::traversal_record_test
