// bvh8's recorded traversal (core/traversal_record.h, bvh8/draw.h) replayed against the kernels'
// own rules: every ISA the CPU runs, both node layouts, all three leaf kinds. The replay below
// re-runs the closest-hit traversal's stack discipline from the steps alone (each visited node's
// children all tested, the entered ones nearest first, deferred ones visited or dropped by the
// closest hit recorded so far), so a step left out, added or out of order breaks it; the result
// is then held to the plain counting path (same nodes, same primitives, same hit) and each box
// decision to a slab test in double.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "support/independent_math.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh8/isa.h"
#include "thicket/scene/scene.h"

namespace thicket::bvh8_traversal_record_test {
namespace {

using Kind = TraversalStep::Kind;

/// 300 random small triangles in the unit cube (many overlapping boxes: deep stacks, skips).
Scene soup() {
    std::mt19937 rng(81);
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

/// 120 small spheres in the unit cube: a set that is not triangles, so leaves list ids
/// (the kernels' callback leaves).
Scene spheres() {
    std::mt19937 rng(82);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), r(0.01f, 0.06f);
    Scene s;
    s.name = "spheres";
    for (int i = 0; i < 120; ++i) s.add_shape(Sphere{{u(rng), u(rng), u(rng)}, r(rng)});
    return s;
}

/// Rays from in front of the cube through it, every direction octant among them.
std::vector<Ray> rays() {
    std::mt19937 rng(83);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    std::vector<Ray> out;
    for (int i = 0; i < 96; ++i) {
        const float side = (i & 1) ? -1.0f : 2.0f;
        Ray r;
        r.org = {u(rng), u(rng), side};
        r.dir = Vec3{u(rng), u(rng), 1.0f - side} - r.org;
        if (i & 2) std::swap(r.org.x, r.org.z), std::swap(r.dir.x, r.dir.z);
        out.push_back(r);
    }
    return out;
}


// Crossings this close (in t; rays ~3 long) to a decision are left out of the slab comparison:
// float and double may decide them differently.
constexpr double kMargin = 1e-4;
// How far (in space: the scene is the unit cube) the FMA slab test may move a plane outward, a
// generous bound of its offsets (about kSlabSlack times the distance to the planes).
constexpr float kGrow = 2e-3f;

/// The tree as for_each_node lists it: each id's box and its children in lane order.
struct Drawn {
    std::map<uint32_t, DrawnNode> nodes;
    std::map<uint32_t, std::vector<uint32_t>> children;
};

Drawn drawn(const Accel& accel) {
    Drawn d;
    std::vector<uint32_t> path;  // the last node listed at each depth: pre-order
    EXPECT_TRUE(accel.for_each_node([&](const DrawnNode& n) {
        EXPECT_TRUE(d.nodes.emplace(n.id, n).second) << "id " << n.id << " listed twice";
        if (n.depth > 0) d.children[path.at(n.depth - 1)].push_back(n.id);
        if (!n.leaf) {
            path.resize(n.depth);
            path.push_back(n.id);
        }
    }));
    return d;
}

/// What a replay found: the nodes visited, in order, and the closest distance at the end.
struct Replayed {
    std::vector<uint32_t> visited;
    float closest;
    uint32_t last_prim = kNoPrim;
};

/// Re-runs the closest-hit traversal's rules on the recorded steps, failing at the first step
/// they do not allow. Also compares each box decision with the slab test (`checked` counts them).
Replayed replay(const Drawn& tree, const Ray& ray, const std::vector<TraversalStep>& steps, size_t& checked,
                const std::string& what) {
    Replayed out{{}, ray.tmax};
    size_t pos = 0;
    const auto next = [&]() -> const TraversalStep& {
        if (pos >= steps.size()) throw std::string("the steps end early");
        return steps[pos++];
    };
    struct Deferred {
        uint32_t id;
        float t;
    };
    std::vector<Deferred> stack;
    try {
        const TraversalStep& root = next();
        if (root.kind != Kind::Enter || root.id != 0 || root.t != ray.tmin) throw std::string("not the root first");
        uint32_t cur = 0;
        for (;;) {
            out.visited.push_back(cur);
            const DrawnNode& node = tree.nodes.at(cur);
            bool descended = false;
            if (node.leaf) {
                for (uint32_t k = 0; k < node.prims; ++k) {
                    const TraversalStep& s = next();
                    if (s.kind != Kind::Prim) throw "leaf " + std::to_string(cur) + ": a primitive missing";
                    if (!(s.t <= out.closest)) throw std::string("the closest hit grew");
                    out.closest = s.t;
                    out.last_prim = s.id;
                }
            } else {
                // Every child tested once: the culled first, then the entered nearest first.
                const std::vector<uint32_t>& kids = tree.children.at(cur);
                std::set<uint32_t> seen;
                std::vector<Deferred> entered;
                for (size_t k = 0; k < kids.size(); ++k) {
                    const TraversalStep& s = next();
                    if (s.kind != Kind::Enter && s.kind != Kind::Cull)
                        throw "node " + std::to_string(cur) + ": a child's test missing";
                    if (!std::count(kids.begin(), kids.end(), s.id) || !seen.insert(s.id).second)
                        throw "node " + std::to_string(cur) + ": step names " + std::to_string(s.id) + ", not a child once";
                    const auto [t_in, t_out] = testing::slab_double(ray, tree.nodes.at(s.id).box);
                    const double end = std::min(t_out, double(out.closest));
                    if (s.kind == Kind::Cull) {
                        if (!entered.empty()) throw std::string("a cull after an entered child");
                        EXPECT_FALSE(t_in <= end - kMargin) << what << ": child " << s.id << " crossed at " << t_in << " but culled";
                    } else {
                        if (!entered.empty() && s.t < entered.back().t)
                            throw "node " + std::to_string(cur) + ": entered children not nearest first";
                        entered.push_back({s.id, s.t});
                        // The FMA slab test is conservative (docs/bvh8.md): it may enter a box
                        // the exact test misses, earlier, by less than kGrow in space.
                        Aabb grown = tree.nodes.at(s.id).box;
                        grown.min = grown.min - Vec3(kGrow), grown.max = grown.max + Vec3(kGrow);
                        const auto [g_in, g_out] = testing::slab_double(ray, grown);
                        EXPECT_FALSE(g_in > std::min(g_out, double(out.closest)) + kMargin)
                            << what << ": child " << s.id << " missed but entered";
                        EXPECT_FALSE(s.t > t_in + kMargin || s.t < g_in - kMargin)
                            << what << ": child " << s.id << " entered at " << s.t << ", box at " << t_in;
                    }
                    checked += t_in <= end - kMargin || t_in > end + kMargin;
                }
                if (!entered.empty()) {
                    for (size_t k = entered.size(); k-- > 1;) stack.push_back(entered[k]);
                    cur = entered[0].id;
                    descended = true;
                }
            }
            if (descended) continue;
            // Deferred children: visited when they start before the closest hit, else dropped.
            bool found = false;
            while (!stack.empty() && !found) {
                const Deferred d = stack.back();
                stack.pop_back();
                if (d.t <= out.closest) {
                    cur = d.id;
                    found = true;
                } else {
                    const TraversalStep& s = next();
                    if (s.kind != Kind::Skip || s.id != d.id || s.t != d.t)
                        throw "node " + std::to_string(d.id) + " beyond the hit not dropped";
                }
            }
            if (!found) break;
        }
        if (pos != steps.size()) throw std::string("steps after the traversal's end");
    } catch (const std::string& why) {
        ADD_FAILURE() << what << ": step " << pos << " of " << steps.size() << ": " << why;
    }
    return out;
}

TEST(Bvh8TraversalRecord, StepsReplayTheTraversalAndAgreeWithItsCountersAndHit) {
    const Scene tris = soup(), shapes = spheres();
    for (Isa isa : cpu_isas()) {
        const std::string level = isa_name(isa);
        // The three leaf kinds (Moller blocks, watertight blocks, ids) in both node layouts.
        const std::pair<const Scene*, std::string> cases[] = {
            {&tris, "bvh8:isa=" + level},
            {&tris, "bvh8:isa=" + level + ",nodes=compressed"},
            {&tris, "bvh8:isa=" + level + ",isect=watertight,nodes=compressed"},
            {&shapes, "bvh8:isa=" + level},
            {&shapes, "bvh8:isa=" + level + ",nodes=compressed,isect=watertight"},
        };
        for (const auto& [scene, spec] : cases) {
            const std::unique_ptr<Accel> accel = build_accel(spec, *scene, 1);
            const Drawn tree = drawn(*accel);
            ASSERT_GT(tree.children.size(), 3u) << spec << ": a tree of a few levels";
            size_t checked = 0, hits = 0, skips = 0, culls = 0;
            for (const Ray& ray : rays()) {
                TraversalRecorder rec;
                const Hit hit = accel->intersect(ray, rec);
                ASSERT_TRUE(rec.detailed) << spec;
                const Hit plain_hit = accel->intersect(ray);
                EXPECT_EQ(hit.prim, plain_hit.prim) << spec;
                EXPECT_EQ(hit.t, plain_hit.t) << spec;
                EXPECT_EQ(hit.u, plain_hit.u) << spec;
                hits += hit.found();
                const Replayed r = replay(tree, ray, rec.steps, checked, spec);
                // The steps end with the traversal's hit: the closest recorded is its distance,
                // and the primitive recorded when it was reached is the one hit.
                if (hit.found()) {
                    EXPECT_EQ(r.closest, hit.t) << spec;
                    const auto reached = std::find_if(rec.steps.begin(), rec.steps.end(), [&](const TraversalStep& s) {
                        return s.kind == Kind::Prim && s.t == hit.t;
                    });
                    ASSERT_NE(reached, rec.steps.end()) << spec;
                    EXPECT_EQ(reached->id, hit.prim) << spec;
                } else {
                    EXPECT_EQ(r.closest, ray.tmax) << spec;
                }
                // The nodes entered and not dropped are the ones the counting path visits.
                RayCounters plain;
                EXPECT_EQ(accel->intersect(ray, plain).prim, hit.prim) << spec;
                const auto count = [&](Kind k) {
                    return uint64_t(std::count_if(rec.steps.begin(), rec.steps.end(),
                                                  [&](const TraversalStep& s) { return s.kind == k; }));
                };
                EXPECT_EQ(count(Kind::Enter) - count(Kind::Skip), plain.nodes) << spec;
                EXPECT_EQ(r.visited.size(), plain.nodes) << spec;
                EXPECT_EQ(count(Kind::Prim), plain.prims) << spec;
                EXPECT_EQ(rec.nodes, plain.nodes) << spec;
                EXPECT_EQ(rec.prims, plain.prims) << spec;
                skips += count(Kind::Skip);
                culls += count(Kind::Cull);
            }
            // The rays reach every rule: hits, culls, deferred nodes dropped.
            EXPECT_GT(hits, 20u) << spec;
            EXPECT_GT(culls, 100u) << spec;
            EXPECT_GT(skips, 5u) << spec;
            EXPECT_GT(checked, 1000u) << spec;
        }
    }
}

TEST(Bvh8TraversalRecord, EveryNodeIsDrawnOnceWithinItsParent) {
    const Scene tris = soup();
    for (const char* spec : {"bvh8", "bvh8:nodes=compressed"}) {
        const std::unique_ptr<Accel> accel = build_accel(spec, tris, 1);
        const Drawn tree = drawn(*accel);
        const AccelStats stats = accel->stats();
        size_t triangles = 0;
        for (const auto& [id, n] : tree.nodes) {
            triangles += n.leaf ? n.prims : 0;
            if (!tree.children.count(id) || std::string(spec) != "bvh8") continue;
            // Full nodes: a lane's box is the union of its child's lanes. (Decoded compressed
            // boxes round outward on each node's own grid, so a child's may stick out.)
            for (uint32_t c : tree.children.at(id)) {
                const Aabb& b = tree.nodes.at(c).box;
                for (int a = 0; a < 3; ++a) {
                    EXPECT_GE(b.min[a], n.box.min[a]) << spec << ": node " << c;
                    EXPECT_LE(b.max[a], n.box.max[a]) << spec << ": node " << c;
                }
            }
        }
        EXPECT_EQ(tree.nodes.size(), stats.nodes) << spec << ": nodes and leaves, as stats counts them";
        EXPECT_EQ(triangles, tris.mesh.triangle_count()) << spec;
    }
}

}  // namespace
}  // namespace thicket::bvh8_traversal_record_test
