// `thicket explore`'s drawings (tools/thicket/explore/explore_draw.h) through the page's request,
// POST /api/nodes, level by level: each structure's elements against the scene and the figures
// the structure reports itself (AccelStats), never against the drawing code's own arithmetic.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>

#include "explore_api.h"
#include "thicket/accel/registry.h"

namespace thicket::explore_draw_test {
namespace {

using nlohmann::json;

/// 80 small random triangles in the unit cube.
Scene soup() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), d(-0.08f, 0.08f);
    Scene s;
    s.name = "soup";
    for (uint32_t t = 0; t < 80; ++t) {
        const Vec3 c{u(rng), u(rng), u(rng)};
        for (int k = 0; k < 3; ++k) s.mesh.positions.push_back(c + Vec3{d(rng), d(rng), d(rng)});
        s.mesh.indices.insert(s.mesh.indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    }
    return s;
}

/// Closed axis-aligned cubes (12 triangles each): a scene TetGen meshes whole.
void add_cube(Scene& s, Vec3 lo, float side) {
    const auto base = uint32_t(s.mesh.positions.size());
    for (int i = 0; i < 8; ++i)
        s.mesh.positions.push_back(lo + Vec3{i & 1 ? side : 0.0f, i & 2 ? side : 0.0f, i & 4 ? side : 0.0f});
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces)
        s.mesh.indices.insert(s.mesh.indices.end(),
                              {base + f[0], base + f[1], base + f[2], base + f[0], base + f[2], base + f[3]});
}

Aabb box_of(const json& j) {
    Aabb b;
    b.min = {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
    b.max = {j[3].get<float>(), j[4].get<float>(), j[5].get<float>()};
    return b;
}
Vec3 vec_of(const json& j) { return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()}; }
bool inside(const Aabb& small, const Aabb& big) {
    return big.contains(small.min) && big.contains(small.max);
}
/// Whether the interiors of a and b meet (touching faces do not count).
bool interiors_meet(const Aabb& a, const Aabb& b) {
    for (int k = 0; k < 3; ++k)
        if (a.max[k] <= b.min[k] || b.max[k] <= a.min[k]) return false;
    return true;
}
/// The leading whole number of a figure such as "412 (1.7 per primitive)".
uint64_t figure(const AccelStats& s, const std::string& key) {
    for (const auto& [k, v] : s.extra)
        if (k == key) return std::stoull(v);
    ADD_FAILURE() << "no figure " << key;
    return 0;
}

/// The SAH cost (core/tree_figures.h: 1 per inner node, 1 per leaf reference, each weighted by its
/// box's area over the root's) of the drawn levels: inner boxes are non-leaf boxes and the cells
/// of planes, the root is depth 0's one element. Empty leaves, not drawn, cost nothing.
double sah_of_drawing(const std::vector<json>& levels) {
    const json& root = levels[0]["planes"].empty() ? levels[0]["boxes"][0]["box"] : levels[0]["planes"][0]["cell"];
    const double root_area = box_of(root).half_area();
    double cost = 0.0;
    for (const json& level : levels) {
        for (const json& p : level["planes"]) cost += box_of(p["cell"]).half_area() / root_area;
        for (const json& b : level["boxes"])
            cost += box_of(b["box"]).half_area() / root_area * (b["leaf"].get<bool>() ? b["prims"].get<double>() : 1.0);
    }
    return cost;
}

struct Drawn {
    std::unique_ptr<explore::Session> session;
    AccelStats stats;
    Scene scene;

    Drawn(Scene s, const std::string& spec) : scene(s) {
        std::vector<std::unique_ptr<Accel>> one;
        one.push_back(build_accel(spec, scene, 1));
        stats = one[0]->stats();
        session = std::make_unique<explore::Session>(std::move(s), std::move(one));
    }
    json at(uint32_t depth) const {
        const explore::Response r = session->handle("POST", "/api/nodes", json{{"depth", depth}}.dump());
        EXPECT_EQ(r.status, 200) << r.body;
        return json::parse(r.body);
    }
    /// Every level's answer, depth 0 to max_depth.
    std::vector<json> levels() const {
        std::vector<json> out{at(0)};
        for (uint32_t d = 1; d <= out[0]["max_depth"].get<uint32_t>(); ++d) out.push_back(at(d));
        return out;
    }
    /// Whether every triangle's centroid lies in one of the boxes (closed boxes).
    void centroids_covered(const std::vector<Aabb>& boxes) const {
        for (size_t t = 0; t < scene.mesh.triangle_count(); ++t) {
            const Vec3 c = (scene.mesh.vertex(t, 0) + scene.mesh.vertex(t, 1) + scene.mesh.vertex(t, 2)) * (1.0f / 3.0f);
            bool in = false;
            for (const Aabb& b : boxes) in = in || b.contains(c);
            EXPECT_TRUE(in) << "triangle " << t << "'s centroid is in no drawn leaf";
        }
    }
};

TEST(ExploreDraw, KdTreePlanesLieInTheirCellsLevelByLevel) {
    const Drawn kd(soup(), "kdtree");
    const Aabb scene_box = kd.scene.bounds();
    const std::vector<json> levels = kd.levels();
    ASSERT_GE(levels.size(), 3u);
    EXPECT_EQ(levels[0]["drawing"], "planes and leaf cells");
    ASSERT_EQ(levels[0]["planes"].size(), 1u);  // the root's plane, across the whole scene
    EXPECT_EQ(box_of(levels[0]["planes"][0]["cell"]).min, scene_box.min);
    EXPECT_EQ(box_of(levels[0]["planes"][0]["cell"]).max, scene_box.max);
    uint64_t planes = 0, leaves = 0, refs = 0;
    std::vector<Aabb> leaf_cells;
    for (const json& level : levels) {
        std::vector<Aabb> cells;  // the cells of one level are pieces of one partition of the scene box
        for (const json& p : level["planes"]) {
            const Aabb cell = box_of(p["cell"]);
            EXPECT_TRUE(inside(cell, scene_box));
            ASSERT_EQ(p["polygon"].size(), 4u);
            int flat_axes = 0;
            for (int a = 0; a < 3; ++a) {
                bool same = true;
                for (const json& c : p["polygon"]) same = same && vec_of(c)[a] == vec_of(p["polygon"][0])[a];
                flat_axes += same;
            }
            EXPECT_EQ(flat_axes, 1) << "a kD-tree plane is perpendicular to exactly one axis: " << p.dump();
            for (const json& c : p["polygon"]) EXPECT_TRUE(cell.contains(vec_of(c))) << p.dump();
            cells.push_back(cell);
        }
        for (const json& b : level["boxes"]) {
            EXPECT_TRUE(b["leaf"].get<bool>());
            EXPECT_GT(b["prims"].get<uint32_t>(), 0u) << "empty leaves are not drawn";
            refs += b["prims"].get<uint64_t>();
            cells.push_back(box_of(b["box"]));
            leaf_cells.push_back(cells.back());
        }
        for (size_t i = 0; i < cells.size(); ++i)
            for (size_t j = i + 1; j < cells.size(); ++j)
                EXPECT_FALSE(interiors_meet(cells[i], cells[j])) << "depth " << level["depth"] << ": cells " << i << ", " << j;
        EXPECT_EQ(level["count"], level["planes"].size() + level["boxes"].size());
        planes += level["planes"].size();
        leaves += level["boxes"].size();
    }
    EXPECT_EQ(planes, kd.stats.nodes - kd.stats.leaves);
    EXPECT_EQ(leaves, kd.stats.leaves - figure(kd.stats, "empty leaves"));
    EXPECT_EQ(refs, figure(kd.stats, "references"));
    kd.centroids_covered(leaf_cells);
    EXPECT_NEAR(sah_of_drawing(levels), kd.stats.sah_cost, 1e-4 * kd.stats.sah_cost);
}

/// Whether two convex polygons in one plane (normal n) meet, up to eps: no separating axis
/// among their edges' in-plane normals.
bool coplanar_convex_meet(const std::vector<Vec3>& a, const std::vector<Vec3>& b, const Vec3& n, float eps) {
    for (const std::vector<Vec3>* poly : {&a, &b})
        for (size_t i = 0; i < poly->size(); ++i) {
            const Vec3 axis = cross(n, (*poly)[(i + 1) % poly->size()] - (*poly)[i]);
            float lo_a = INFINITY, hi_a = -INFINITY, lo_b = INFINITY, hi_b = -INFINITY;
            for (const Vec3& p : a) lo_a = std::min(lo_a, dot(axis, p)), hi_a = std::max(hi_a, dot(axis, p));
            for (const Vec3& p : b) lo_b = std::min(lo_b, dot(axis, p)), hi_b = std::max(hi_b, dot(axis, p));
            const float tol = eps * length(axis);
            if (hi_a < lo_b - tol || hi_b < lo_a - tol) return false;
        }
    return true;
}

TEST(ExploreDraw, BspPlanesAreClippedToTheirSideOfEveryAncestor) {
    const Drawn bsp(soup(), "bsp");
    const Aabb scene_box = bsp.scene.bounds();
    const std::vector<json> levels = bsp.levels();
    ASSERT_GE(levels.size(), 3u);
    EXPECT_EQ(levels[0]["drawing"], "planes");
    ASSERT_EQ(levels[0]["planes"].size(), 1u);
    // The root's plane: its polygon spans the scene box, every corner on one of the box's faces.
    const json& root = levels[0]["planes"][0]["polygon"];
    ASSERT_GE(root.size(), 3u);
    const float eps = 1e-4f;
    for (const json& c : root) {
        const Vec3 p = vec_of(c);
        bool on_face = false;
        for (int a = 0; a < 3; ++a)
            on_face = on_face || std::fabs(p[a] - scene_box.min[a]) < eps || std::fabs(p[a] - scene_box.max[a]) < eps;
        EXPECT_TRUE(on_face) << c.dump();
    }
    const Vec3 o = vec_of(root[0]);
    const Vec3 n = normalize(cross(vec_of(root[1]) - o, vec_of(root[2]) - o));
    uint64_t planes = 0;
    for (const json& level : levels) {
        for (const json& p : level["planes"]) {
            const json& q = p["polygon"];
            ASSERT_GE(q.size(), 3u);
            const Vec3 qo = vec_of(q[0]);
            const Vec3 qn = normalize(cross(vec_of(q[1]) - qo, vec_of(q[2]) - qo));
            int below = 0, above = 0;
            for (const json& c : q) {
                const Vec3 v = vec_of(c);
                Aabb grown = scene_box;
                grown.min -= Vec3{eps, eps, eps};
                grown.max += Vec3{eps, eps, eps};
                EXPECT_TRUE(grown.contains(v)) << c.dump();
                EXPECT_NEAR(dot(qn, v - qo), 0.0f, eps) << "a polygon lies in one plane";
                const float side = dot(n, v - o);
                below += side < -eps;
                above += side > eps;
            }
            // Autopartition: the plane is a triangle's, and that triangle's piece in the cell lies
            // in the clipped polygon, so some scene triangle in this plane meets it.
            std::vector<Vec3> poly;
            for (const json& c : q) poly.push_back(vec_of(c));
            bool holds_its_triangle = false;
            for (size_t t = 0; t < bsp.scene.mesh.triangle_count() && !holds_its_triangle; ++t) {
                std::vector<Vec3> tri;
                for (int k = 0; k < 3; ++k) tri.push_back(bsp.scene.mesh.vertex(t, k));
                bool in_plane = true;
                for (const Vec3& v : tri) in_plane = in_plane && std::fabs(dot(qn, v - qo)) < eps;
                holds_its_triangle = in_plane && coplanar_convex_meet(poly, tri, qn, eps);
            }
            EXPECT_TRUE(holds_its_triangle) << "depth " << level["depth"] << ": no triangle of this plane in it: " << p.dump();
            if (level["depth"] != 0) {
                EXPECT_TRUE(below == 0 || above == 0)
                    << "depth " << level["depth"] << ": a plane crosses the root's, so it is not clipped to its cell";
            }
        }
        planes += level["planes"].size();
    }
    EXPECT_GT(planes, 0u);
    EXPECT_LE(planes, bsp.stats.nodes - bsp.stats.leaves);
}

TEST(ExploreDraw, GridsDrawTheirNonEmptyCellsOnly) {
    const Drawn grid(soup(), "grid");
    const json g = grid.at(0);
    EXPECT_EQ(g["drawing"], "cells");
    EXPECT_EQ(g["max_depth"], 0);
    EXPECT_EQ(g["count"], grid.stats.leaves);  // the grid's leaves are its non-empty cells
    uint64_t refs = 0;
    std::vector<Aabb> cells;
    for (const json& b : g["boxes"]) {
        EXPECT_GT(b["prims"].get<uint32_t>(), 0u);
        refs += b["prims"].get<uint64_t>();
        cells.push_back(box_of(b["box"]));
    }
    EXPECT_EQ(refs, figure(grid.stats, "references"));
    grid.centroids_covered(cells);

    const Drawn grid2(soup(), "grid2");
    const std::vector<json> levels = grid2.levels();
    ASSERT_EQ(levels.size(), 2u);
    EXPECT_EQ(levels[1]["count"], grid2.stats.leaves);
    std::vector<Aabb> top, sub;
    for (const json& b : levels[0]["boxes"]) top.push_back(box_of(b["box"]));
    refs = 0;
    for (const json& b : levels[1]["boxes"]) {
        EXPECT_GT(b["prims"].get<uint32_t>(), 0u);
        refs += b["prims"].get<uint64_t>();
        sub.push_back(box_of(b["box"]));
        bool in_top = false;
        for (const Aabb& t : top) in_top = in_top || inside(sub.back(), t);
        EXPECT_TRUE(in_top) << "a sub-grid cell outside every drawn top cell: " << b.dump();
    }
    EXPECT_EQ(refs, figure(grid2.stats, "references"));
    grid2.centroids_covered(sub);
}

/// Checks a box hierarchy level by level: depth 0 is one box holding `root`, each deeper box lies
/// in an inner box of the level above, leaves are non-empty and hold every triangle's centroid.
/// Returns the number of leaves drawn.
size_t check_box_levels(const Drawn& d, const std::vector<json>& levels, const Aabb& root) {
    EXPECT_EQ(levels[0]["boxes"].size(), 1u);
    EXPECT_TRUE(inside(root, box_of(levels[0]["boxes"][0]["box"])));
    std::vector<Aabb> leaves, inner;
    for (const json& level : levels) {
        std::vector<Aabb> next;
        for (const json& b : level["boxes"]) {
            const Aabb box = box_of(b["box"]);
            if (level["depth"] != 0) {
                bool in_parent = false;
                for (const Aabb& p : inner) in_parent = in_parent || inside(box, p);
                EXPECT_TRUE(in_parent) << "depth " << level["depth"] << ": " << b.dump();
            }
            if (b["leaf"].get<bool>()) {
                EXPECT_GT(b["prims"].get<uint32_t>(), 0u);
                leaves.push_back(box);
            } else {
                next.push_back(box);
            }
        }
        inner = next;
    }
    d.centroids_covered(leaves);
    return leaves.size();
}

TEST(ExploreDraw, OctreeCellsAndBihIntervalsNestLevelByLevel) {
    const Drawn oct(soup(), "octree");
    const std::vector<json> o = oct.levels();
    ASSERT_GE(o.size(), 2u);
    EXPECT_EQ(o[0]["drawing"], "cells");
    EXPECT_EQ(check_box_levels(oct, o, oct.scene.bounds()), oct.stats.leaves - figure(oct.stats, "empty leaves"));
    EXPECT_NEAR(sah_of_drawing(o), oct.stats.sah_cost, 1e-4 * oct.stats.sah_cost);

    const Drawn bih(soup(), "bih");
    const std::vector<json> b = bih.levels();
    ASSERT_GE(b.size(), 2u);
    EXPECT_EQ(b[0]["drawing"], "boxes");
    EXPECT_EQ(box_of(b[0]["boxes"][0]["box"]).max, bih.scene.bounds().max);
    EXPECT_EQ(check_box_levels(bih, b, bih.scene.bounds()), bih.stats.leaves - figure(bih.stats, "empty leaves"));
    EXPECT_NEAR(sah_of_drawing(b), bih.stats.sah_cost, 1e-4 * bih.stats.sah_cost);
}

TEST(ExploreDraw, ObbLeavesHoldTheirTriangles) {
    const Drawn obb(soup(), "obb");
    const std::vector<json> levels = obb.levels();
    EXPECT_EQ(levels[0]["drawing"], "oriented boxes");
    uint64_t nodes = 0;
    std::vector<json> leaves;
    for (const json& level : levels) {
        nodes += level["oriented"].size();
        for (const json& o : level["oriented"]) {
            const Vec3 a[3] = {vec_of(o["axes"][0]), vec_of(o["axes"][1]), vec_of(o["axes"][2])};
            for (int i = 0; i < 3; ++i)
                for (int j = i + 1; j < 3; ++j) EXPECT_NEAR(dot(a[i], a[j]), 0.0f, 1e-5f) << o.dump();
            if (o["leaf"].get<bool>()) leaves.push_back(o);
        }
    }
    EXPECT_EQ(nodes, obb.stats.nodes);
    // Every corner of every triangle is inside (up to rounding) some leaf's oriented box.
    for (size_t t = 0; t < obb.scene.mesh.triangle_count(); ++t)
        for (int c = 0; c < 3; ++c) {
            const Vec3 p = obb.scene.mesh.vertex(t, c);
            bool in = false;
            for (const json& o : leaves) {
                bool here = true;
                for (int k = 0; k < 3; ++k) {
                    const Vec3 h = vec_of(o["axes"][k]);
                    here = here && std::fabs(dot(p - vec_of(o["center"]), h)) <= dot(h, h) * (1.0f + 1e-4f) + 1e-6f;
                }
                in = in || here;
            }
            EXPECT_TRUE(in) << "triangle " << t << " corner " << c << " is in no leaf's oriented box";
        }
}

TEST(ExploreDraw, TetrahedraByStepsFromTheSurface) {
    Scene s;
    s.name = "two cubes";
    add_cube(s, {0, 0, 0}, 1.0f);
    add_cube(s, {3, 0.5f, 0}, 0.5f);
    const Drawn tet(s, "tetra");
    const std::vector<json> levels = tet.levels();
    ASSERT_GE(levels.size(), 2u);
    EXPECT_EQ(levels[0]["drawing"], "tetrahedra");
    uint64_t total = 0;
    for (const json& level : levels) {
        EXPECT_GT(level["tetrahedra"].size(), 0u) << "no tetrahedron at depth " << level["depth"];
        total += level["tetrahedra"].size();
    }
    EXPECT_EQ(total, figure(tet.stats, "tetrahedra"));
    // Steps across faces: a tetrahedron at depth k >= 1 shares a face with one at depth k - 1 and
    // none with one nearer the surface (faces matched by their sorted corners).
    using Face = std::array<std::array<float, 3>, 3>;
    const auto faces_of = [](const json& t) {
        std::vector<Face> out;
        for (int skip = 0; skip < 4; ++skip) {
            Face f;
            size_t n = 0;
            for (int k = 0; k < 4; ++k)
                if (k != skip) f[n++] = t["corners"][size_t(k)].get<std::array<float, 3>>();
            std::sort(f.begin(), f.end());
            out.push_back(f);
        }
        return out;
    };
    std::map<Face, uint32_t> nearest;  // the smallest depth of a tetrahedron with that face
    for (const json& level : levels)
        for (const json& t : level["tetrahedra"])
            for (const Face& f : faces_of(t)) nearest.emplace(f, level["depth"].get<uint32_t>());
    for (size_t k = 1; k < levels.size(); ++k)
        for (const json& t : levels[k]["tetrahedra"]) {
            uint32_t lowest = uint32_t(k);
            for (const Face& f : faces_of(t)) lowest = std::min(lowest, nearest[f]);
            EXPECT_EQ(lowest, k - 1) << "depth " << k << ": " << t.dump();
        }
    // Depth 0 touches the surface: each has a face whose three corners lie on a cube's faces
    // (corners of the cubes, or points TetGen added on them).
    const auto on_surface = [&](const Vec3& p) {
        const float eps = 1e-5f;
        for (const auto& [lo, side] : {std::pair{Vec3{0, 0, 0}, 1.0f}, {Vec3{3, 0.5f, 0}, 0.5f}}) {
            bool within = true, on_face = false;
            for (int a = 0; a < 3; ++a) {
                within = within && p[a] >= lo[a] - eps && p[a] <= lo[a] + side + eps;
                on_face = on_face || std::fabs(p[a] - lo[a]) < eps || std::fabs(p[a] - lo[a] - side) < eps;
            }
            if (within && on_face) return true;
        }
        return false;
    };
    for (const json& t : levels[0]["tetrahedra"]) {
        int on = 0;
        for (const json& c : t["corners"]) on += on_surface(vec_of(c));
        EXPECT_GE(on, 3) << t.dump();
    }
}

TEST(ExploreDraw, LargeLevelsAreSampledAcrossTheWholeLevel) {
    // A flat square in a 230 x 230 grid: 52,900 non-empty cells, just over the limit of one answer.
    Scene s;
    s.name = "square";
    s.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    s.mesh.indices = {0, 1, 2, 0, 2, 3};
    const Drawn grid(s, "grid:res=230");
    const json g = grid.at(0);
    const uint64_t count = g["count"];
    ASSERT_GT(count, explore::kMaxBoxes);
    EXPECT_TRUE(g["truncated"].get<bool>());
    const uint64_t stride = g["stride"];
    EXPECT_EQ(stride, (count + explore::kMaxBoxes - 1) / explore::kMaxBoxes);
    EXPECT_EQ(g["drawn"], g["boxes"].size());
    EXPECT_LE(g["boxes"].size(), explore::kMaxBoxes);
    EXPECT_EQ(g["boxes"].size(), (count + stride - 1) / stride);
    // Every k-th cell, not the first ones: the drawn cells reach across the square.
    Aabb spanned;
    for (const json& b : g["boxes"]) spanned.grow(box_of(b["box"]));
    EXPECT_GT(spanned.max.y - spanned.min.y, 0.95f);
    EXPECT_GT(spanned.max.x - spanned.min.x, 0.95f);
}

/// The box around everything one level's answer draws: boxes, plane corners, oriented boxes'
/// corners, tetrahedra's corners.
Aabb extent_of_level(const json& level) {
    Aabb e;
    for (const json& b : level["boxes"]) e.grow(box_of(b["box"]));
    for (const json& p : level["planes"])
        for (const json& q : p["polygon"]) e.grow(vec_of(q));
    for (const json& o : level["oriented"]) {
        const Vec3 c = vec_of(o["center"]);
        for (int k = 0; k < 8; ++k) {
            Vec3 q = c;
            for (int a = 0; a < 3; ++a) q = q + vec_of(o["axes"][a]) * (k >> a & 1 ? 1.0f : -1.0f);
            e.grow(q);
        }
    }
    for (const json& t : level["tetrahedra"])
        for (const json& q : t["corners"]) e.grow(vec_of(q));
    return e;
}

TEST(ExploreDraw, EveryRegisteredStructureDrawsItselfButBruteForce) {
    // The explorer names no structure: whatever the registry holds, the next one included, is
    // drawn through Accel::for_each_node, level by level, and its drawing spans the scene.
    Scene s;  // closed cubes, which tetra meshes whole
    s.name = "cubes";
    add_cube(s, {0, 0, 0}, 1.0f);
    add_cube(s, {2, 0.5f, 0}, 0.5f);
    add_cube(s, {0.5f, 2, 1}, 0.25f);
    for (const AccelInfo& info : accel_registry()) {
        SCOPED_TRACE(info.name);
        const Drawn d(s, info.name);
        const explore::Response r = d.session->handle("POST", "/api/nodes", json{{"depth", 0}}.dump());
        if (info.name == "brute") {
            EXPECT_EQ(r.status, 422);
            continue;
        }
        ASSERT_EQ(r.status, 200) << r.body;
        EXPECT_FALSE(json::parse(r.body)["drawing"].get<std::string>().empty());
        EXPECT_FALSE(json::parse(r.body)["depth_means"].get<std::string>().empty());
        Aabb drawn;
        for (const json& level : d.levels()) {
            EXPECT_GT(level["count"].get<uint64_t>(), 0u) << "an empty level below max_depth";
            drawn.grow(extent_of_level(level));
        }
        const float slack = 1e-4f;
        for (size_t t = 0; t < s.mesh.triangle_count(); ++t) {
            const Vec3 c = (s.mesh.vertex(t, 0) + s.mesh.vertex(t, 1) + s.mesh.vertex(t, 2)) * (1.0f / 3.0f);
            for (int a = 0; a < 3; ++a) {
                EXPECT_GE(c[a], drawn.min[a] - slack) << "triangle " << t << " lies outside everything drawn";
                EXPECT_LE(c[a], drawn.max[a] + slack) << "triangle " << t << " lies outside everything drawn";
            }
        }
    }
}

TEST(ExploreDraw, BruteForceIsRefusedWithWhatDraws) {
    const Drawn brute(soup(), "brute");
    const explore::Response r = brute.session->handle("POST", "/api/nodes", "{}");
    EXPECT_EQ(r.status, 422);
    EXPECT_NE(r.body.find("\"brute:"), std::string::npos) << r.body;
    EXPECT_NE(r.body.find("does not draw its nodes (docs/explore.md"), std::string::npos) << r.body;
    EXPECT_EQ(json::parse(brute.session->handle("GET", "/api/scene", "").body)["structures"][0]["draws_nodes"], false);
}

}  // namespace
}  // namespace thicket::explore_draw_test
