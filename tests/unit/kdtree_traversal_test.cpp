// kD-tree traversals against brute force on the cases the conformance rays meet only by chance:
// rays lying in split planes, through cell edges and corners, flat scenes, -0 directions,
// non-finite and non-triangle primitives, hits reported across cell boundaries, mailboxing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <sstream>

#include "kdtree_test_scenes.h"
#include "support/probe.h"
#include "support/reference.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/brute/brute_force.h"
#include "thicket/core/error.h"
#include "thicket/kdtree/kdtree.h"
#include "thicket/prims/triangles.h"

namespace thicket::kdtree_traversal_test {
namespace {

using Tris = Triangles<>;
using namespace kdtest;

// ---- traversal --------------------------------------------------------------------------------

const char* const kSpecs[] = {"kdtree:traversal=stack", "kdtree:traversal=restart",
                              "kdtree:builder=median,traversal=stack", "kdtree:builder=median,traversal=restart"};

/// Every spec answers every ray like brute force, tests no primitive twice, and -0/+0 in the
/// direction make no difference.
void expect_like_brute_force(const Scene& scene, const std::vector<Ray>& rays) {
    auto brute = build_accel("brute", scene);
    const testing::PrimitiveProbe probe(scene, "moller");
    std::vector<Hit> hits;
    std::vector<uint8_t> occluded;
    for (const Ray& r : rays) {
        hits.push_back(brute->intersect(r));
        occluded.push_back(brute->occluded(r));
    }
    for (const char* spec : kSpecs) {
        SCOPED_TRACE(spec);
        auto accel = build_accel(spec, scene);
        size_t bad = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            const Ray& r = rays[i];
            RayCounters c;
            const Hit want = hits[i], got = accel->intersect(r, c);
            const bool ok = testing::same_closest_hit(got, want, r, probe) && accel->occluded(r) == bool(occluded[i]);
            if (!ok && bad++ < 3)
                ADD_FAILURE() << "ray org (" << r.org.x << ", " << r.org.y << ", " << r.org.z << ") dir (" << r.dir.x
                              << ", " << r.dir.y << ", " << r.dir.z << "): got prim " << got.prim << " t " << got.t
                              << ", brute force prim " << want.prim << " t " << want.t;
            EXPECT_LE(c.prims, scene.primitive_count()) << "mailboxing: each primitive at most once per query";
        }
        EXPECT_EQ(bad, 0u);
    }
}

/// Rays lying exactly in split planes of the tree (direction component +0 or -0 on the plane's
/// axis, origin on the plane), in both directions along the other axes.
std::vector<Ray> rays_in_split_planes(const Scene& scene, size_t planes) {
    auto accel = build_accel("kdtree", scene);
    const KdTreeData& t = dynamic_cast<const KdTree<Tris>&>(*accel).data();
    std::mt19937 rng(17);
    const Aabb b = scene.bounds();
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Ray> rays;
    size_t used = 0;
    for (size_t i = 0; i < t.nodes.size() && used < planes; i += 1 + rng() % 7) {
        const KdNode& n = t.nodes[i];
        if (n.is_leaf()) continue;
        ++used;
        const int a = n.axis(), b1 = (a + 1) % 3, b2 = (a + 2) % 3;
        for (int k = 0; k < 4; ++k) {
            Vec3 o, d;
            o[a] = n.split();
            o[b1] = b.min[b1] - 0.1f * (b.max[b1] - b.min[b1]);
            o[b2] = b.min[b2] + u(rng) * (b.max[b2] - b.min[b2]);
            d[a] = k % 2 ? -0.0f : 0.0f;
            d[b1] = 1.0f;
            d[b2] = k < 2 ? 0.0f : u(rng) - 0.5f;
            rays.push_back({o, 0.0f, d, kInfinity});
            // The same line traversed the other way.
            Ray back{o + d * 3.0f * (b.max[b1] - b.min[b1] + 1.0f), 0.0f, -d, kInfinity};
            back.org[a] = n.split();
            rays.push_back(back);
        }
    }
    return rays;
}

/// Rays aimed exactly at corners of leaf voxels (where two or three split planes meet) and
/// rays starting on split planes.
std::vector<Ray> rays_at_voxel_corners(const Scene& scene, size_t count) {
    auto accel = build_accel("kdtree", scene);
    const KdTreeData& t = dynamic_cast<const KdTree<Tris>&>(*accel).data();
    std::vector<Aabb> voxels;
    struct Item {
        uint32_t node;
        Aabb voxel;
    };
    std::vector<Item> stack{{0, t.bounds}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const KdNode& n = t.nodes[it.node];
        if (n.is_leaf()) {
            voxels.push_back(it.voxel);
            continue;
        }
        Aabb below = it.voxel, above = it.voxel;
        below.max[n.axis()] = above.min[n.axis()] = n.split();
        stack.push_back({it.node + 1, below});
        stack.push_back({n.above(), above});
    }
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const Aabb b = scene.bounds();
    const float scale = max_component(b.extent());
    std::vector<Ray> rays;
    for (size_t i = 0; i < count; ++i) {
        const Aabb& v = voxels[rng() % voxels.size()];
        const int c = int(rng() % 8);
        const Vec3 corner(c & 1 ? v.max.x : v.min.x, c & 2 ? v.max.y : v.min.y, c & 4 ? v.max.z : v.min.z);
        const Vec3 o = b.center() + Vec3(u(rng), u(rng), u(rng)) * scale;
        rays.push_back({o, 0.0f, corner - o, kInfinity});
        rays.push_back({corner, 0.0f, Vec3(u(rng), u(rng), u(rng)), kInfinity});  // starts on planes
    }
    return rays;
}

TEST(KdTraversal, RaysLyingInSplitPlanesSeeBothSides) {
    // Axis-aligned geometry puts many primitives in the very planes the tree splits at.
    const Scene scene = mixed_scene(9, 1500);
    expect_like_brute_force(scene, rays_in_split_planes(scene, 300));
    const Scene cube = testing::nasty_scenes()[8];  // the closed, subdivided cube
    ASSERT_EQ(cube.name, "closed-cube");
    expect_like_brute_force(cube, rays_in_split_planes(cube, 200));
}

TEST(KdTraversal, RaysThroughVoxelCornersAndStartingOnPlanes) {
    const Scene scene = mixed_scene(10, 1500);
    expect_like_brute_force(scene, rays_at_voxel_corners(scene, 2000));
    const auto files = testing::shared_scene_files();
    for (const std::string& file : files)
        if (file.find("sponza") != std::string::npos) {
            const Scene sponza = subsample(testing::cached_scene(file), 10000, 7);
            expect_like_brute_force(sponza, rays_at_voxel_corners(sponza, 1500));
        }
}

TEST(KdTraversal, FlatScenesAndAxisParallelRays) {
    // Every triangle in z = 0: the root voxel is flat, so are all cells.
    TriangleMesh m;
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 800; ++i) {
        const Vec3 c(u(rng), u(rng), 0.0f);
        add_triangle(m, c, c + Vec3(0.05f * u(rng), 0.05f * u(rng), 0.0f), c + Vec3(-0.05f * u(rng), 0.05f * u(rng), 0.0f));
    }
    const Scene flat = make_scene("flat", std::move(m));
    std::vector<Ray> rays = testing::conformance_rays(flat, 2000, 3);
    for (int i = 0; i < 500; ++i) {
        const Vec3 p(u(rng), u(rng), 0.0f);
        for (float z : {1.0f, -1.0f}) rays.push_back({p + Vec3(0, 0, z), 0.0f, Vec3(-0.0f, 0.0f, -z), kInfinity});
        rays.push_back({p, 0.0f, Vec3(u(rng) - 0.5f, u(rng) - 0.5f, 0.5f), kInfinity});  // starts on the surface
        rays.push_back({Vec3(-1.0f, p.y, 0.0f), 0.0f, Vec3(1.0f, 0.0f, 0.0f), kInfinity});  // lies in the plane
    }
    expect_like_brute_force(flat, rays);
}

TEST(KdTraversal, SignOfZeroDirectionComponentsDoesNotMatter) {
    const Scene scene = mixed_scene(11, 1000);
    for (const char* spec : kSpecs) {
        auto accel = build_accel(spec, scene);
        for (const Ray& r : testing::conformance_rays(scene, 3000, 5)) {
            Ray flipped = r;
            bool any_zero = false;
            for (int a = 0; a < 3; ++a)
                if (r.dir[a] == 0.0f) {
                    flipped.dir[a] = std::signbit(r.dir[a]) ? 0.0f : -0.0f;
                    any_zero = true;
                }
            if (!any_zero) continue;
            const Hit x = accel->intersect(r), y = accel->intersect(flipped);
            ASSERT_EQ(x.prim, y.prim) << spec;
            ASSERT_EQ(x.t, y.t) << spec;
        }
    }
}

TEST(KdTraversal, NonFinitePrimitivesAreLeftOutAndNeverHit) {
    Scene scene = mixed_scene(12, 300);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    add_triangle(scene.mesh, {nan, 0, 0}, {1, 0, 0}, {0, 1, 0});
    add_triangle(scene.mesh, {kInfinity, 0, 0}, {1, 1, 0}, {0, 1, 1});
    const KdTree<Tris> tree(Tris(scene.mesh), KdBuildOptions{});
    EXPECT_FALSE(tree.bounds().empty());
    for (int a = 0; a < 3; ++a) EXPECT_TRUE(std::isfinite(tree.bounds().min[a]) && std::isfinite(tree.bounds().max[a]));
    std::vector<Ray> rays = testing::conformance_rays(mixed_scene(12, 300), 2000, 9);
    expect_like_brute_force(scene, rays);
}

/// Axis-aligned cubes as primitives: a set without clip() or triangle(), so the builder falls
/// back to bounds intersected with the voxel, and the traversal must not assume triangles.
class Cubes {
public:
    explicit Cubes(std::vector<Aabb> boxes) : boxes_(std::move(boxes)) {}
    size_t size() const { return boxes_.size(); }
    size_t bytes() const { return boxes_.size() * sizeof(Aabb); }
    Aabb bounds(uint32_t i) const { return boxes_[i]; }
    Vec3 centroid(uint32_t i) const { return boxes_[i].center(); }
    bool intersect(uint32_t i, const Ray& ray, Hit& hit) const {
        const float t = ray_box_entry(RayBoxQuery(ray), boxes_[i], ray.tmin, hit.t);
        if (t == kInfinity || !(t <= hit.t)) return false;
        hit = {t, 0.0f, 0.0f, i};
        return true;
    }
    bool occludes(uint32_t i, const Ray& ray) const {
        return ray_box_entry(RayBoxQuery(ray), boxes_[i], ray.tmin, ray.tmax) != kInfinity;
    }

private:
    std::vector<Aabb> boxes_;
};
static_assert(PrimitiveSet<Cubes>);
static_assert(!kHasTriangles<Cubes>);

TEST(KdTraversal, WorksForPrimitivesOtherThanTriangles) {
    std::mt19937 rng(41);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Aabb> boxes;
    for (int i = 0; i < 600; ++i) {
        const Vec3 c(u(rng) * 10.0f, u(rng) * 10.0f, u(rng) * 10.0f);
        const Vec3 h = Vec3(u(rng), u(rng), u(rng)) * (i % 10 == 0 ? 2.0f : 0.3f);
        boxes.push_back({c - h, c + h});
    }
    const Cubes cubes(boxes);
    const BruteForce<Cubes> brute(cubes);
    for (KdTraversal traversal : {KdTraversal::Stack, KdTraversal::Restart}) {
        const KdTree<Cubes> kd(cubes, KdBuildOptions{}, traversal);
        EXPECT_GT(kdtree_figures(kd.data()).leaves, 50u);
        for (int i = 0; i < 3000; ++i) {
            const Vec3 o(u(rng) * 14.0f - 2.0f, u(rng) * 14.0f - 2.0f, u(rng) * 14.0f - 2.0f);
            Vec3 d(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f);
            if (i % 4 == 0) d[i % 3] = 0.0f;
            const Ray r{o, 0.0f, d, kInfinity};
            const Hit a = brute.intersect(r), b = kd.intersect(r);
            ASSERT_EQ(a.found(), b.found()) << i;
            if (a.found()) {
                ASSERT_EQ(a.t, b.t) << i;
            }
            ASSERT_EQ(brute.occluded(r), kd.occluded(r)) << i;
        }
    }
}

/// Walls x = const (bounded in y and z) whose reported hit distance may come out early by a
/// relative `early`, as a triangle test's t may be off by rounding, and which record every test.
class Walls {
public:
    struct Wall {
        float x;
        Vec3 lo, hi;  ///< y and z extents (x ignored)
        float early;
    };
    explicit Walls(std::vector<Wall> walls) : walls_(std::move(walls)) {}
    size_t size() const { return walls_.size(); }
    size_t bytes() const { return walls_.size() * sizeof(Wall); }
    Aabb bounds(uint32_t i) const {
        const Wall& w = walls_[i];
        return {Vec3(w.x, w.lo.y, w.lo.z), Vec3(w.x, w.hi.y, w.hi.z)};
    }
    Vec3 centroid(uint32_t i) const { return bounds(i).center(); }
    bool intersect(uint32_t i, const Ray& ray, Hit& hit) const {
        const float t = test(i, ray);
        if (!(t >= ray.tmin && t <= hit.t)) return false;
        hit = {t, 0.0f, 0.0f, i};
        return true;
    }
    bool occludes(uint32_t i, const Ray& ray) const {
        const float t = test(i, ray);
        return t >= ray.tmin && t <= ray.tmax;
    }
    mutable std::vector<uint32_t> tested;

private:
    float test(uint32_t i, const Ray& ray) const {
        tested.push_back(i);
        const Wall& w = walls_[i];
        if (ray.dir.x == 0.0f) return kInfinity;
        const float t = (w.x - ray.org.x) / ray.dir.x;
        const Vec3 p = ray.org + ray.dir * t;
        if (p.y < w.lo.y || p.y > w.hi.y || p.z < w.lo.z || p.z > w.hi.z) return kInfinity;
        return t * (1.0f - w.early);
    }
    std::vector<Wall> walls_;
};
static_assert(PrimitiveSet<Walls>);

TEST(KdTraversal, AHitInTheNextCellReportedJustBeforeTheCurrentOneIsNotLost) {
    // Wall A lies just below the plane x = 10, wall B just above it but reports its t early (as
    // Moller-Trumbore may, by up to about 1e-5 relative), before A's. Brute force answers B, so
    // the above cell must be visited although it starts after A's hit: the query ends only once
    // the cells left start beyond the hit by more than kSlabSlack.
    const Walls walls({{9.9999f, Vec3(0.0f), Vec3(1.0f), 0.0f}, {10.00005f, Vec3(0.0f), Vec3(1.0f), 5e-5f}});
    KdTreeData tree;
    tree.primitives = 2;
    tree.nodes.push_back(KdNode::interior(0, 10.0f, 2));
    tree.nodes.push_back(KdNode::leaf(0, 1));
    tree.nodes.push_back(KdNode::leaf(1, 1));
    tree.prim_indices = {0, 1};
    tree.bounds = walls.bounds(0);
    tree.bounds.grow(walls.bounds(1));
    ASSERT_NO_THROW(validate_kdtree(tree, 2));
    const Ray ray{{0.0f, 0.5f, 0.5f}, 0.0f, {1.0f, 0.0f, 0.0f}, kInfinity};
    const BruteForce<Walls> brute(walls);
    ASSERT_EQ(brute.intersect(ray).prim, 1u);
    for (KdTraversal traversal : {KdTraversal::Stack, KdTraversal::Restart}) {
        NoCounters none;
        const Hit hit = closest_hit<kd_detail::KdQuery>(tree, walls, ray, none, traversal);
        EXPECT_EQ(hit.prim, 1u) << (traversal == KdTraversal::Stack ? "stack" : "restart");
        EXPECT_EQ(hit.t, brute.intersect(ray).t);
    }
}

TEST(KdTraversal, MailboxingTestsEachPrimitiveOncePerQuery) {
    // Walls spanning the whole scene in y and z are cut into many leaves, and rays along x meet
    // several leaves referencing the same wall: each wall is tested at most once per query.
    std::mt19937 rng(43);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Walls::Wall> list;
    for (int i = 0; i < 400; ++i) {
        const Vec3 c(0.0f, u(rng) * 10.0f, u(rng) * 10.0f);
        const float half = i % 8 == 0 ? 10.0f : 0.3f;
        list.push_back({u(rng) * 10.0f, c - Vec3(half), c + Vec3(half), 0.0f});
    }
    const Walls walls(list);
    for (KdTraversal traversal : {KdTraversal::Stack, KdTraversal::Restart}) {
        const KdTree<Walls> kd(walls, KdBuildOptions{}, traversal);
        EXPECT_GT(kdtree_figures(kd.data()).references, 2 * walls.size()) << "big walls are referenced by many leaves";
        size_t tests = 0;
        for (int i = 0; i < 2000; ++i) {
            const Ray ray{{-1.0f, u(rng) * 10.0f, u(rng) * 10.0f}, 0.0f, {1.0f, u(rng) - 0.5f, u(rng) - 0.5f}, kInfinity};
            std::vector<uint32_t>& tested = kd.primitives().tested;  // the tree holds its own copy
            tested.clear();
            if (i % 2)
                kd.intersect(ray);
            else
                kd.occluded(ray);
            std::sort(tested.begin(), tested.end());
            ASSERT_EQ(std::adjacent_find(tested.begin(), tested.end()), tested.end()) << "a wall tested twice by one query";
            tests += tested.size();
        }
        EXPECT_GT(tests, 2000u);
    }
}


}  // namespace
}  // namespace thicket::kdtree_traversal_test
