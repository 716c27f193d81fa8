// The box tests' far-end slack (issue 45): bvh8's traversal tests boxes against [tmin, hit.t]
// widened by kSlabSlack relative at each end, so a box entered just beyond the current hit is
// still visited (rounding of the hit's t must not lose a nearer primitive in it), and nothing
// entered beyond that window is. The answers alone cannot show the second half (a wider window
// is slower, never wrong), so these tests count the nodes visited on hand-made trees whose boxes
// are entered just inside and just outside the window, under every ISA this CPU runs.
#include <gtest/gtest.h>

#include <string>

#include "thicket/accel/registry.h"
#include "thicket/bvh8/foreign_tree.h"
#include "thicket/core/isa.h"
#include "thicket/core/ray_box.h"
#include "thicket/scene/scene.h"

namespace thicket::bvh8_box_slack_test {
namespace {

using bvh8::WideTree;

// Entry distances for a hit at t = 1 (the window ends at 1 + kSlabSlack): halfway into the
// window, and as far again beyond its end.
constexpr float kInside = 1.0f + 0.5f * kSlabSlack;
constexpr float kBeyond = 1.0f + 2.0f * kSlabSlack;

/// The tree the test's builder hands to bvh8 (a function pointer cannot capture it).
WideTree g_tree;
WideTree hand_made_tree(const bvh8::ForeignTreeRequest&) { return g_tree; }

/// Installs hand_made_tree as the foreign builder for one scope (the unit tests link no Embree,
/// so none was installed before).
struct ScopedHandMadeTree {
    explicit ScopedHandMadeTree(WideTree tree) {
        g_tree = std::move(tree);
        bvh8::set_foreign_tree_builder(&hand_made_tree);
    }
    ~ScopedHandMadeTree() { bvh8::set_foreign_tree_builder(nullptr); }
};

/// A triangle in the plane z = `z` around (x, 0): it covers the z axis when x = 0.
void add_triangle(Scene& scene, float x, float z) {
    const uint32_t base = uint32_t(scene.mesh.positions.size());
    scene.mesh.positions.insert(scene.mesh.positions.end(),
                                {Vec3(x - 1, -1, z), Vec3(x + 1, -1, z), Vec3(x, 1, z)});
    scene.mesh.indices.insert(scene.mesh.indices.end(), {base, base + 1, base + 2});
}

Aabb triangle_box(const Scene& scene, uint32_t t) {
    Aabb b;
    for (int k = 0; k < 3; ++k) b.grow(scene.mesh.positions[scene.mesh.indices[3 * t + k]]);
    return b;
}

WideTree::Item leaf(const Scene& scene, uint32_t prim) { return {triangle_box(scene, prim), prim, 1, true}; }

/// Root over two leaves: triangle 0 at z = 1 and triangle 1 at z = `second`, both on the z axis.
/// A ray up the axis hits 0 first; the second leaf waits on the stack and is popped after the hit.
WideTree popped_after_the_hit(Scene& scene, float second) {
    add_triangle(scene, 0, 1);
    add_triangle(scene, 0, second);
    WideTree t;
    Aabb all = triangle_box(scene, 0);
    all.grow(triangle_box(scene, 1));
    t.items = {{all, 0, 2, false}, leaf(scene, 0), leaf(scene, 1)};
    t.children = {1, 2};
    t.prims = {0, 1};
    return t;
}

/// Root over a leaf (triangle 0 at z = 1) and an interior node entered at kInside / 2 whose
/// children are triangle 1 at z = `second` on the axis and triangle 2 off the axis (at x = 4):
/// the interior node is visited after the hit, and its box test decides on the second leaf.
WideTree tested_after_the_hit(Scene& scene, float second) {
    add_triangle(scene, 0, 1);
    add_triangle(scene, 0, second);
    add_triangle(scene, 4, 1.0f + 0.25f * kSlabSlack);
    WideTree t;
    Aabb inner = triangle_box(scene, 1);
    inner.grow(triangle_box(scene, 2));
    Aabb all = inner;
    all.grow(triangle_box(scene, 0));
    t.items = {{all, 0, 2, false}, leaf(scene, 0), {inner, 2, 2, false}, leaf(scene, 1), leaf(scene, 2)};
    t.children = {1, 2, 3, 4};
    t.prims = {0, 1, 2};
    return t;
}

const Ray kUpTheAxis{{0, 0, 0}, 0.0f, {0, 0, 1}, kInfinity};

/// Nodes (interior and leaves) the counting closest-hit traversal visits for kUpTheAxis, on
/// every ISA; every ISA must count the same and find triangle 0 at t = 1.
uint64_t closest_visits(WideTree (*make)(Scene&, float), float second) {
    Scene scene;
    const ScopedHandMadeTree installed(make(scene, second));
    uint64_t visits = 0;
    for (Isa isa : cpu_isas()) {
        const auto accel = build_accel(std::string("bvh8:tree=embree-medium,isa=") + isa_name(isa), scene);
        RayCounters c;
        const Hit hit = accel->intersect(kUpTheAxis, c);
        EXPECT_EQ(hit.prim, 0u) << isa_name(isa);
        EXPECT_EQ(hit.t, 1.0f) << isa_name(isa);
        if (visits == 0) visits = c.nodes;
        EXPECT_EQ(c.nodes, visits) << isa_name(isa) << " visits what the others visit";
    }
    return visits;
}

TEST(Bvh8BoxSlack, ALeafPoppedAfterTheHitIsVisitedOnlyWithinTheWindow) {
    EXPECT_EQ(closest_visits(popped_after_the_hit, kInside), 3u) << "root, the hit's leaf, the leaf in the window";
    EXPECT_EQ(closest_visits(popped_after_the_hit, kBeyond), 2u) << "the leaf beyond the window is dropped";
}

TEST(Bvh8BoxSlack, ABoxTestedAfterTheHitEntersOnlyWithinTheWindow) {
    EXPECT_EQ(closest_visits(tested_after_the_hit, kInside), 4u) << "root, hit leaf, interior, the leaf in the window";
    EXPECT_EQ(closest_visits(tested_after_the_hit, kBeyond), 3u) << "its box test culls the leaf beyond the window";
}

// Any hit has no hit to shrink to: the window sits at the end of the ray's own interval.
TEST(Bvh8BoxSlack, AnyHitVisitsBoxesWithinTheWindowPastTmaxOnly) {
    Scene scene;
    const ScopedHandMadeTree installed(popped_after_the_hit(scene, 3.0f));
    for (Isa isa : cpu_isas()) {
        SCOPED_TRACE(isa_name(isa));
        const auto accel = build_accel(std::string("bvh8:tree=embree-medium,isa=") + isa_name(isa), scene);
        // Triangle 0 at t = 1 lies just beyond tmax: within the window its leaf is visited (and
        // its triangle, beyond tmax, not hit); beyond the window the root alone is.
        for (const auto& [tmax, visits] : {std::pair{1.0f - 0.5f * kSlabSlack, 2u}, std::pair{1.0f - 2.0f * kSlabSlack, 1u}}) {
            Ray ray = kUpTheAxis;
            ray.tmax = tmax;
            RayCounters c;
            EXPECT_FALSE(accel->occluded(ray, c)) << "tmax " << tmax;
            EXPECT_EQ(c.nodes, visits) << "tmax " << tmax;
        }
    }
}

}  // namespace
}  // namespace thicket::bvh8_box_slack_test
