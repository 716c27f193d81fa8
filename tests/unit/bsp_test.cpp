#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <sstream>

#include "support/probe.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bsp/bsp.h"
#include "thicket/brute/brute_force.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"

namespace thicket::bsp_test {
namespace {

using Polygon = std::vector<std::array<double, 3>>;

Scene nasty(const std::string& name) {
    for (Scene& s : testing::nasty_scenes())
        if (s.name == name) return std::move(s);
    throw Error("no nasty scene " + name);
}

std::vector<std::array<Vec3, 3>> triangles_of(const Scene& scene) {
    std::vector<std::array<Vec3, 3>> tris(scene.primitive_count());
    for (uint32_t i = 0; i < tris.size(); ++i)
        tris[i] = {scene.mesh.vertex(i, 0), scene.mesh.vertex(i, 1), scene.mesh.vertex(i, 2)};
    return tris;
}

std::array<double, 3> sub(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const std::array<double, 3>& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
std::array<double, 3> d3(const Vec3& v) { return {v.x, v.y, v.z}; }

double polygon_area(const Polygon& p) {
    std::array<double, 3> sum{0, 0, 0};
    for (size_t k = 1; k + 1 < p.size(); ++k) {
        const auto c = cross(sub(p[k], p[0]), sub(p[k + 1], p[0]));
        for (int a = 0; a < 3; ++a) sum[a] += c[a];
    }
    return 0.5 * norm(sum);
}

double triangle_area(const std::array<Vec3, 3>& t) {
    return 0.5 * norm(cross(sub(d3(t[1]), d3(t[0])), sub(d3(t[2]), d3(t[0]))));
}

double distance(const BspPlane& p, const std::array<double, 3>& x) {
    return double(p.normal.x) * x[0] + double(p.normal.y) * x[1] + double(p.normal.z) * x[2] - double(p.offset);
}

/// For every leaf, the planes on its path from the root and the side taken (true: front).
std::map<uint32_t, std::vector<std::pair<BspPlane, bool>>> leaf_paths(const BspData& bsp) {
    std::map<uint32_t, std::vector<std::pair<BspPlane, bool>>> out;
    struct Item {
        uint32_t node;
        std::vector<std::pair<BspPlane, bool>> path;
    };
    std::vector<Item> stack;
    if (!bsp.nodes.empty()) stack.push_back({0, {}});
    while (!stack.empty()) {
        Item it = std::move(stack.back());
        stack.pop_back();
        const BspNode& node = bsp.nodes[it.node];
        if (node.is_leaf()) {
            out[it.node] = it.path;
            continue;
        }
        for (bool front : {false, true}) {
            Item child{node.index + (front ? 1u : 0u), it.path};
            child.path.emplace_back(node.plane, front);
            stack.push_back(std::move(child));
        }
    }
    return out;
}

struct Built {
    BspData bsp;
    std::vector<BspFragment> fragments;
};

Built build(const Scene& scene, const BspBuildOptions& o = {}) {
    Built b;
    b.bsp = build_bsp_triangles(triangles_of(scene), o, &b.fragments);
    return b;
}

TEST(BspLayout, NodeIsThirtyTwoBytesAndPoolIsCacheAligned) {
    EXPECT_EQ(sizeof(BspNode), 32u);
    const Built b = build(nasty("soup"));
    EXPECT_EQ(reinterpret_cast<uintptr_t>(b.bsp.nodes.data()) % 64, 0u);
}

TEST(BspFragments, TileTheirTriangleExactly) {
    for (const char* name : {"soup", "coplanar", "same-centroid", "closed-cube", "huge", "tiny"}) {
        SCOPED_TRACE(name);
        const Scene scene = nasty(name);
        const auto tris = triangles_of(scene);
        const Built b = build(scene);
        std::vector<double> area(tris.size(), 0.0);
        std::vector<int> count(tris.size(), 0);
        for (const BspFragment& f : b.fragments) {
            ASSERT_LT(f.prim, tris.size());
            ASSERT_GE(f.polygon.size(), 3u) << "a fragment is a polygon";
            area[f.prim] += polygon_area(f.polygon);
            ++count[f.prim];
            // Every vertex lies in its triangle's plane (pieces are cut in double).
            const auto& t = tris[f.prim];
            const auto n = cross(sub(d3(t[1]), d3(t[0])), sub(d3(t[2]), d3(t[0])));
            const double len = norm(n);
            if (len == 0.0) continue;
            for (const auto& v : f.polygon) {
                const auto r = sub(v, d3(t[0]));
                const double off = std::fabs(n[0] * r[0] + n[1] * r[1] + n[2] * r[2]) / len;
                EXPECT_LE(off, 1e-9 * b.bsp.scale + 1e-30) << "fragment vertex off its triangle's plane";
            }
        }
        size_t cut = 0;
        for (size_t i = 0; i < tris.size(); ++i) {
            EXPECT_GE(count[i], 1) << "triangle " << i << " is in no leaf";
            const double want = triangle_area(tris[i]);
            EXPECT_NEAR(area[i], want, 1e-9 * want + 1e-300) << "fragments of triangle " << i << " do not tile it";
            cut += count[i] > 1 ? 1 : 0;
        }
        if (std::string(name) == "soup") {
            EXPECT_GT(cut, 0u) << "the soup must make the builder cut triangles";
        }
    }
}

TEST(BspFragments, LieOnTheirSideOfEveryPlaneOnTheirPath) {
    for (const char* name : {"soup", "coplanar", "same-centroid", "closed-cube", "duplicates"}) {
        for (BspCost cost : {BspCost::Sah, BspCost::Balance}) {
            SCOPED_TRACE(std::string(name) + (cost == BspCost::Sah ? " sah" : " balance"));
            BspBuildOptions o;
            o.cost = cost;
            o.max_leaf = 1;
            const Built b = build(nasty(name), o);
            const auto paths = leaf_paths(b.bsp);
            // The builder's in-plane tolerance is half of this.
            const double tolerance = double(kBspPlaneBand) * b.bsp.scale;
            size_t checked = 0;
            for (const BspFragment& f : b.fragments) {
                const auto it = paths.find(f.leaf);
                ASSERT_NE(it, paths.end()) << "fragment in node " << f.leaf << ", which is not a leaf";
                for (const auto& [plane, front] : it->second)
                    for (const auto& v : f.polygon) {
                        const double d = distance(plane, v);
                        if (front)
                            EXPECT_GE(d, -tolerance);
                        else
                            EXPECT_LE(d, tolerance);
                        ++checked;
                    }
            }
            EXPECT_GT(checked, 0u);
        }
    }
}

TEST(BspBuild, PureAutopartitionPlanesPassThroughTheSceneTriangles) {
    // Without the axis fallback every plane is a triangle's own plane or one of its edge planes:
    // it holds at least two vertices of some triangle.
    for (const char* name : {"soup", "coplanar", "closed-cube"}) {
        SCOPED_TRACE(name);
        const Scene scene = nasty(name);
        const auto tris = triangles_of(scene);
        BspBuildOptions o;
        o.axis_fallback = false;
        const Built b = build(scene, o);
        const double tolerance = double(kBspPlaneBand) * b.bsp.scale;
        size_t planes = 0;
        for (const BspNode& n : b.bsp.nodes) {
            if (n.is_leaf()) continue;
            ++planes;
            bool found = false;
            for (size_t t = 0; t < tris.size() && !found; ++t) {
                int on = 0;
                for (const Vec3& v : tris[t]) on += std::fabs(distance(n.plane, d3(v))) <= tolerance ? 1 : 0;
                found = on >= 2;
            }
            EXPECT_TRUE(found) << "plane (" << n.plane.normal.x << ", " << n.plane.normal.y << ", " << n.plane.normal.z
                               << ") . p = " << n.plane.offset << " holds no triangle's edge";
        }
        EXPECT_GT(planes, 0u);
    }
}

TEST(BspFragments, SplinterStatisticsMatchTheFragments) {
    const Scene scene = nasty("soup");
    const auto tris = triangles_of(scene);
    const Built b = build(scene);
    const BspSplinters& s = b.bsp.splinters;
    EXPECT_TRUE(s.polygons);
    EXPECT_EQ(s.fragments, b.fragments.size());
    EXPECT_EQ(s.fragments, b.bsp.refs.size());
    // Every triangle starts as one fragment; each cut adds one; polygons are never dropped.
    EXPECT_EQ(s.fragments, tris.size() + s.splits);
    EXPECT_EQ(s.dropped, 0u);
    EXPECT_GT(s.splits, 0u);

    std::vector<int> count(tris.size(), 0);
    for (const BspFragment& f : b.fragments) ++count[f.prim];
    uint64_t split = 0, pieces = 0, slivers = 0;
    double smallest = INFINITY, smallest_ratio = INFINITY;
    for (const BspFragment& f : b.fragments) {
        if (count[f.prim] < 2) continue;
        const double a = polygon_area(f.polygon), ratio = a / triangle_area(tris[f.prim]);
        ++pieces;
        smallest = std::min(smallest, a);
        smallest_ratio = std::min(smallest_ratio, ratio);
        slivers += ratio < kBspSliverRatio ? 1 : 0;
    }
    for (int c : count) split += c > 1 ? 1 : 0;
    EXPECT_EQ(s.split_triangles, split);
    EXPECT_EQ(s.pieces, pieces);
    EXPECT_EQ(s.measured_pieces, pieces) << "the soup has no zero-area triangle";
    EXPECT_EQ(s.slivers, slivers);
    EXPECT_NEAR(s.smallest_area, smallest, 1e-12 * smallest + 1e-300);
    EXPECT_NEAR(s.smallest_ratio, smallest_ratio, 1e-9);

    // The same figures through the Accel interface.
    Bsp<Triangles<>> bsp(Triangles<>(scene.mesh), BspBuildOptions{});
    const AccelStats st = bsp.stats();
    auto extra = [&](const std::string& key) {
        for (const auto& [k, v] : st.extra)
            if (k == key) return v;
        ADD_FAILURE() << "no statistic '" << key << "'";
        return std::string();
    };
    EXPECT_EQ(extra("fragments"), std::to_string(s.fragments));
    EXPECT_EQ(extra("fragments created by splits"), std::to_string(s.splits));
    EXPECT_EQ(extra("primitives split"), std::to_string(split));
    EXPECT_EQ(std::stod(extra("fragments per primitive")), std::round(1000.0 * double(s.fragments) / tris.size()) / 1000.0);
    EXPECT_EQ(st.bytes, b.bsp.nodes.size() * sizeof(BspNode) + b.bsp.refs.size() * sizeof(uint32_t));
}

TEST(BspBuild, LimitsHold) {
    const Scene scene = nasty("soup");
    for (int budget : {1, 2, 8}) {
        for (int depth : {0, 3, 48}) {
            SCOPED_TRACE("budget " + std::to_string(budget) + ", depth " + std::to_string(depth));
            BspBuildOptions o;
            o.fragment_budget = budget;
            o.max_depth = depth;
            const Built b = build(scene, o);
            const BspFigures f = bsp_figures(b.bsp);
            EXPECT_LE(b.bsp.splinters.fragments, uint64_t(budget) * scene.primitive_count());
            EXPECT_LE(f.max_depth, size_t(depth));
            if (budget == 1) {
                EXPECT_EQ(b.bsp.splinters.splits, 0u) << "a budget of 1 never cuts a triangle";
            }
            // A leaf over max-leaf is always accounted for by one of the caps.
            size_t big = 0;
            for (const BspNode& n : b.bsp.nodes) big += n.is_leaf() && n.leaf_size() > size_t(o.max_leaf) ? 1 : 0;
            const BspSplinters& s = b.bsp.splinters;
            EXPECT_EQ(big, s.depth_capped + s.budget_capped + s.unsplittable);
            if (depth == 0) {
                EXPECT_EQ(f.nodes, 1u);
            }
        }
    }
}

TEST(BspBuild, BadOptionsAreErrorsNamingTheValue) {
    const auto tris = triangles_of(nasty("one-triangle"));
    auto expect_error = [&](BspBuildOptions o, const std::string& needle) {
        try {
            build_bsp_triangles(tris, o);
            ADD_FAILURE() << "no error for " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    BspBuildOptions o;
    o.candidates = 0;
    expect_error(o, "candidates=0");
    o = {};
    o.max_depth = int(kBspMaxDepth) + 1;
    expect_error(o, "max-depth=101");
    o = {};
    o.fragment_budget = 0;
    expect_error(o, "fragment-budget=0");
    o = {};
    o.max_leaf = 0;
    expect_error(o, "max-leaf=0");
    EXPECT_THROW(parse_accel_spec("bsp:candidates=0"), Error);
    EXPECT_THROW(parse_accel_spec("bsp:cost=best"), Error);
    EXPECT_THROW(parse_accel_spec("bsp:fallback=kd"), Error);
}

TEST(BspBuild, EmptyAndSingleTriangleScenes) {
    const Scene empty = nasty("empty");
    Bsp<Triangles<>> e(Triangles<>(empty.mesh), BspBuildOptions{});
    EXPECT_TRUE(e.bounds().empty());
    EXPECT_FALSE(e.intersect({{0, 0, 1}, 0.0f, {0, 0, -1}, kInfinity}).found());
    EXPECT_FALSE(e.occluded({{0, 0, 1}, 0.0f, {0, 0, -1}, kInfinity}));

    const Scene one = nasty("one-triangle");
    Bsp<Triangles<>> b(Triangles<>(one.mesh), BspBuildOptions{});
    const Hit h = b.intersect({{0.2f, 0.2f, 1}, 0.0f, {0, 0, -1}, kInfinity});
    EXPECT_EQ(h.prim, 0u);
    EXPECT_FLOAT_EQ(h.t, 1.0f);
    EXPECT_EQ(b.stats().nodes, 1u);
}

/// Compares closest and any hits against brute force ray for ray, by the suite's agreement rule
/// (support/probe.h): the same primitive with identical t, u, v, or a real tie.
template <class A, class B>
void expect_same_answers(const A& got, const B& want, const TriangleMesh& mesh, const std::vector<Ray>& rays) {
    const testing::PrimitiveProbe probe(mesh, "moller");
    size_t hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Ray& r = rays[i];
        const Hit a = got.intersect(r), b = want.intersect(r);
        ASSERT_EQ(a.found(), b.found()) << "ray " << i;
        hits += b.found();
        EXPECT_TRUE(testing::same_closest_hit(a, b, r, probe))
            << "ray " << i << ": prim " << a.prim << " t " << a.t << " uv " << a.u << "," << a.v << " vs prim " << b.prim
            << " t " << b.t << " uv " << b.u << "," << b.v;
        ASSERT_EQ(got.occluded(r), want.occluded(r)) << "ray " << i;
    }
    EXPECT_GT(hits, 0u);
}

/// Rays lying in, parallel to, and crossing exactly at the planes of an axis-aligned box room
/// (floor, walls, a tessellated coplanar plate): the builder's planes are those planes.
TEST(BspTraversal, RaysInAndAlongSplitPlanesAndHitsOnThem) {
    TriangleMesh m;
    auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
        const auto base = uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {a, b, c, d});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    };
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const float x = float(i) * 0.25f, z = float(j) * 0.25f;
            quad({x, 0, z}, {x + 0.25f, 0, z}, {x + 0.25f, 0, z + 0.25f}, {x, 0, z + 0.25f});  // floor y = 0
        }
    quad({0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1});                      // wall x = 0
    quad({1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0});                      // wall x = 1
    quad({0.2f, 0.5f, 0.2f}, {0.8f, 0.5f, 0.2f}, {0.8f, 0.5f, 0.8f}, {0.2f, 0.5f, 0.8f});  // plate y = 0.5
    quad({0.3f, 0.25f, 0.3f}, {0.7f, 0.75f, 0.3f}, {0.7f, 0.75f, 0.7f}, {0.3f, 0.25f, 0.7f});  // slanted
    Scene scene;
    scene.name = "room";
    scene.mesh = m;

    std::vector<Ray> rays;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-0.1f, 1.1f);
    for (int i = 0; i < 400; ++i) {
        // Lying in the planes y = 0, y = 0.5, x = 0, x = 1, and in the slanted plane.
        const float a = u(rng), b = u(rng), c = u(rng);
        rays.push_back({{a, 0.0f, -0.5f}, 0.0f, {0.0f, 0.0f, 1.0f}, kInfinity});
        rays.push_back({{-0.5f, 0.5f, b}, 0.0f, {1.0f, 0.0f, c - 0.5f}, kInfinity});
        rays.push_back({{0.0f, a, -0.5f}, 0.0f, {0.0f, b - 0.5f, 1.0f}, kInfinity});
        rays.push_back({{1.0f, -0.5f, c}, 0.0f, {-0.0f, 1.0f, 0.0f}, kInfinity});
        rays.push_back({{0.3f, 0.25f, a}, 0.0f, {0.4f, 0.5f, 0.0f}, kInfinity});
        // Parallel to them, just off; and through shared edges and vertices of the floor.
        rays.push_back({{a, 1e-7f, -0.5f}, 0.0f, {0.0f, 0.0f, 1.0f}, kInfinity});
        rays.push_back({{a, 0.5f + 1e-6f, -0.5f}, 0.0f, {0.0f, -0.0f, 1.0f}, kInfinity});
        const float gx = float(int(b * 4.0f)) * 0.25f, gz = float(int(c * 4.0f)) * 0.25f;
        rays.push_back({{gx, 2.0f, gz}, 0.0f, {0.0f, -1.0f, 0.0f}, kInfinity});
        rays.push_back({{gx + a, 2.0f, gz + b}, 0.0f, {-a, -2.0f, -b}, kInfinity});
        // Starting on a plane, leaving it, with a window that ends exactly on a plane.
        rays.push_back({{a, 0.5f, b}, 0.0f, {c, 1.0f - c, 0.3f}, kInfinity});
        rays.push_back({{a, 1.0f, b}, 0.0f, {0.0f, -1.0f, 0.0f}, 0.5f});
    }
    for (const Ray& r : testing::conformance_rays(scene, 2000)) rays.push_back(r);

    const BruteForce<Triangles<>> brute{Triangles<>(scene.mesh)};
    for (bool fallback : {true, false})
        for (int max_leaf : {1, 4}) {
            SCOPED_TRACE("fallback " + std::to_string(fallback) + ", max-leaf " + std::to_string(max_leaf));
            BspBuildOptions o;
            o.axis_fallback = fallback;
            o.max_leaf = max_leaf;
            const Bsp<Triangles<>> bsp(Triangles<>(scene.mesh), o);
            EXPECT_GT(bsp.stats().nodes, 1u);
            expect_same_answers(bsp, brute, scene.mesh, rays);
        }
}

/// A primitive set that is not triangles to the BSP: it hides triangle() and clip(), so the
/// builder falls back to axis-aligned planes from the bounds.
class BoxOnlyTriangles {
public:
    explicit BoxOnlyTriangles(const TriangleMesh& mesh) : tris_(mesh) {}
    size_t size() const { return tris_.size(); }
    size_t bytes() const { return tris_.bytes(); }
    Aabb bounds(uint32_t i) const { return tris_.bounds(i); }
    Vec3 centroid(uint32_t i) const { return tris_.centroid(i); }
    bool intersect(uint32_t i, const Ray& r, Hit& h) const { return tris_.intersect(i, r, h); }
    bool occludes(uint32_t i, const Ray& r) const { return tris_.occludes(i, r); }

private:
    Triangles<> tris_;
};
static_assert(!kHasTriangles<BoxOnlyTriangles>);

TEST(BspFallback, NonTriangleSetsUseAxisPlanesAndAgreeWithBruteForce) {
    for (const Scene& scene : testing::nasty_scenes()) {
        SCOPED_TRACE(scene.name);
        const BruteForce<BoxOnlyTriangles> brute{BoxOnlyTriangles(scene.mesh)};
        std::vector<BspFragment> fragments;
        BspBuildOptions o;
        o.max_leaf = 2;
        const Bsp<BoxOnlyTriangles> bsp(BoxOnlyTriangles(scene.mesh), o, &fragments);
        const BspData& d = bsp.data();
        EXPECT_FALSE(d.splinters.polygons);
        for (const BspNode& n : d.nodes) {
            if (n.is_leaf()) continue;
            const Vec3 a = abs(n.plane.normal);
            EXPECT_EQ(a.x + a.y + a.z, 1.0f) << "an axis-aligned plane";
        }
        // Every fragment box lies on its side of every plane on its path, exactly.
        const auto paths = leaf_paths(d);
        for (const BspFragment& f : fragments) {
            EXPECT_TRUE(f.polygon.empty());
            for (const auto& [plane, front] : paths.at(f.leaf)) {
                const int axis = plane.normal.x != 0 ? 0 : (plane.normal.y != 0 ? 1 : 2);
                if (front)
                    EXPECT_GE(f.box.min[axis], plane.offset);
                else
                    EXPECT_LE(f.box.max[axis], plane.offset);
            }
        }
        if (scene.primitive_count() == 0) continue;
        if (scene.name == "soup") {
            EXPECT_GT(d.splinters.splits, 0u);
        }
        expect_same_answers(bsp, brute, scene.mesh, testing::conformance_rays(scene, 1500, 5));
    }
}

TEST(BspTraversal, CountsEachPrimitiveOnceAndCountingChangesNothing) {
    const Scene scene = nasty("soup");
    BspBuildOptions o;
    o.max_leaf = 1;
    const Bsp<Triangles<>> bsp(Triangles<>(scene.mesh), o);
    ASSERT_GT(bsp.data().splinters.split_triangles, 0u);
    for (const Ray& r : testing::conformance_rays(scene, 500, 3)) {
        RayCounters c;
        const Hit a = bsp.intersect(r, c), b = bsp.intersect(r);
        EXPECT_EQ(a.prim, b.prim);
        EXPECT_EQ(a.t, b.t);
        EXPECT_LE(c.prims, scene.primitive_count()) << "mailboxing: no primitive is tested twice";
        if (a.found()) {
            EXPECT_GE(c.nodes, 1u);
        }
    }
}

TEST(BspIo, RoundTripAndCorruptPayloadsAreRefused) {
    const Scene scene = nasty("soup");
    const Bsp<Triangles<>> bsp(Triangles<>(scene.mesh), BspBuildOptions{});
    std::ostringstream out;
    bsp.save(out);
    {
        std::istringstream in(out.str());
        const Bsp<Triangles<>> loaded(Triangles<>(scene.mesh), read_bsp(in, scene.primitive_count()));
        EXPECT_EQ(loaded.data().nodes.size(), bsp.data().nodes.size());
        EXPECT_EQ(loaded.data().refs, bsp.data().refs);
        EXPECT_EQ(loaded.stats().extra, bsp.stats().extra);
        for (const Ray& r : testing::conformance_rays(scene, 300, 4)) EXPECT_EQ(loaded.intersect(r).prim, bsp.intersect(r).prim);
    }
    auto refused = [&](const std::string& payload, size_t prims, const std::string& needle) {
        std::istringstream in(payload);
        try {
            read_bsp(in, prims);
            ADD_FAILURE() << "accepted a payload that should say: " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    const std::string good = out.str();
    refused(good.substr(0, good.size() / 2), scene.primitive_count(), "truncated");
    refused(good + "x", scene.primitive_count(), "trailing");
    refused(good, 10, "reference to primitive");
    // Edit the tree in memory and check validate_bsp names each defect.
    auto broken = [&](auto edit, const std::string& needle) {
        BspData d = bsp.data();
        edit(d);
        try {
            validate_bsp(d, scene.primitive_count());
            ADD_FAILURE() << "validate_bsp accepted: " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    ASSERT_FALSE(bsp.data().nodes[0].is_leaf());
    broken([](BspData& d) { d.nodes[0].index = 0; }, "children out of range");
    broken([](BspData& d) { d.nodes[0].index = uint32_t(d.nodes.size() - 1); }, "children out of range");
    broken([](BspData& d) { d.nodes[0].plane.normal = Vec3(2, 0, 0); }, "no unit plane");
    broken([](BspData& d) { d.nodes[0].plane.offset = NAN; }, "no unit plane");
    broken([](BspData& d) { d.refs.push_back(0); }, "leaves cover");
    broken([](BspData& d) { d.nodes.emplace_back(); }, "unreachable");
    broken([](BspData& d) {
        for (BspNode& n : d.nodes)
            if (n.is_leaf()) n.count = BspNode::kLeafBit | 0x7fffffffu;
    }, "references out of range");
}

}  // namespace
}  // namespace thicket::bsp_test
