// What only the grids have: the resolution rule, cell lists on a scene small enough to count by
// hand, exact cell assignment, the per-ray mailbox, the cell cap, and DDA edge cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "support/probe.h"
#include "support/reference.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/brute/brute_force.h"
#include "thicket/core/error.h"
#include "thicket/grid/grid.h"
#include "thicket/grid/grid2.h"
#include "thicket/prims/triangles.h"

namespace thicket::grid_test {
namespace {

void add_triangle(TriangleMesh& m, Vec3 a, Vec3 b, Vec3 c) {
    const auto base = uint32_t(m.positions.size());
    m.positions.insert(m.positions.end(), {a, b, c});
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
}

const Scene& nasty(const std::string& name) {
    static const std::vector<Scene> scenes = testing::nasty_scenes();
    for (const Scene& s : scenes)
        if (s.name == name) return s;
    throw Error("no nasty scene " + name);
}

GridOptions grid_options(uint32_t res, GridAssign assign, bool mailbox = true) {
    GridOptions o;
    o.res = res;
    o.assign = assign;
    o.mailbox = mailbox;
    return o;
}

// ---- resolution rule -------------------------------------------------------------------------

TEST(GridResolution, DensityRuleFollowsTheBoxShape) {
    EXPECT_EQ(density_resolution({1, 1, 1}, 1000, 1000, kMaxGridCells).n, (std::array<uint32_t, 3>{10, 10, 10}));
    // s^3 * (1 * 0.5 * 0.5) = 16000 -> s = 40: 40 x 20 x 20 cells.
    EXPECT_EQ(density_resolution({2, 1, 1}, 16000, 1000, kMaxGridCells).n, (std::array<uint32_t, 3>{40, 20, 20}));
    // lambda * N = 5 * 200 = 1000 cells for a cube.
    EXPECT_EQ(density_resolution({3, 3, 3}, 5.0 * 200, 1000, kMaxGridCells).cells(), 1000u);
}

TEST(GridResolution, FlatAndThinAxesGetOneCellAndLeaveTheBudgetToTheOthers) {
    EXPECT_EQ(density_resolution({1, 1, 0}, 100, 1000, kMaxGridCells).n, (std::array<uint32_t, 3>{10, 10, 1}));
    EXPECT_EQ(density_resolution({1, 1e-6f, 1}, 100, 1000, kMaxGridCells).n, (std::array<uint32_t, 3>{10, 1, 10}));
    EXPECT_EQ(density_resolution({0, 0, 5}, 100, 1000, kMaxGridCells).n, (std::array<uint32_t, 3>{1, 1, 100}));
    EXPECT_EQ(density_resolution({0, 0, 0}, 100, 1000, kMaxGridCells).cells(), 1u);
    EXPECT_EQ(density_resolution({kInfinity, 1, 1}, 100, 1000, kMaxGridCells).cells(), 1u);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(density_resolution({nan, 1, 1}, 100, 1000, kMaxGridCells).cells(), 1u);
}

TEST(GridResolution, AutomaticResolutionIsCappedPerAxisAndInAll) {
    const GridResolution big = density_resolution({1, 1, 1}, 1e15, 1u << 30, kMaxGridCells);
    EXPECT_LE(big.cells(), kMaxGridCells);
    EXPECT_GE(big.cells(), kMaxGridCells / 2) << "scaled down, not collapsed";
    const GridResolution line = density_resolution({1, 0, 0}, 1e6, 255, kMaxGridCells);
    EXPECT_EQ(line.n, (std::array<uint32_t, 3>{255, 1, 1}));
}

TEST(GridResolution, ExplicitResCountsAlongTheLongestAxis) {
    EXPECT_EQ(longest_axis_resolution({4, 2, 1}, 8, "t").n, (std::array<uint32_t, 3>{8, 4, 2}));
    EXPECT_EQ(longest_axis_resolution({1, 4, 0}, 8, "t").n, (std::array<uint32_t, 3>{2, 8, 1}));
    try {
        longest_axis_resolution({1, 1, 1}, 4096, "grid: res=4096");
        FAIL() << "4096^3 cells must be refused";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("res=4096"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("67108864"), std::string::npos) << e.what();
    }
}

TEST(GridResolution, AbsurdSpecsAreClearErrorsNotAllocations) {
    const Scene& scene = nasty("soup");  // a cube-shaped box: res=4096 would be 6.9e10 cells
    EXPECT_THROW(build_accel("grid:res=4096", scene), Error);
    EXPECT_THROW(build_accel("grid:res=5000", scene), Error);
    EXPECT_THROW(build_accel("grid:lambda=0", scene), Error);
    EXPECT_THROW(build_accel("grid2:top=0", scene), Error);
    EXPECT_NO_THROW(build_accel("grid:res=100", scene));
}

TEST(GridResolution, GridUsesLambdaTimesNCells) {
    const Scene& scene = nasty("soup");  // 2000 triangles
    for (int lambda : {1, 5, 16}) {
        GridOptions o;
        o.lambda = lambda;
        const Grid<Triangles<>> grid(Triangles<>(scene.mesh), o);
        const double want = lambda * 2000.0, got = double(grid.data().frame.cells());
        EXPECT_GT(got, want * 0.6) << "lambda " << lambda;
        EXPECT_LT(got, want * 1.6) << "lambda " << lambda;
    }
}

// ---- cell lists on a scene counted by hand ---------------------------------------------------

/// Box [0,4]^3, res=4: unit cells. A small triangle in cell (0,0,0); a triangle in the plane
/// z = 3.5 bounded by x >= 0.5, y >= 0.5, x + y <= 4, whose bounding box spans the 4 x 4 cells of
/// layer z = 3 but which touches only the 13 with i + j <= 4 (those with i + j == 4 only at a
/// corner of the hypotenuse); a small triangle in cell (3,3,3) reaching the far corner.
Scene counted_scene() {
    TriangleMesh m;
    add_triangle(m, {0, 0, 0}, {0.9f, 0.1f, 0.1f}, {0.1f, 0.9f, 0.1f});
    add_triangle(m, {0.5f, 0.5f, 3.5f}, {3.5f, 0.5f, 3.5f}, {0.5f, 3.5f, 3.5f});
    add_triangle(m, {4, 4, 4}, {3.2f, 3.9f, 3.9f}, {3.9f, 3.2f, 3.9f});
    Scene s;
    s.name = "counted";
    s.mesh = std::move(m);
    return s;
}

TEST(GridCells, ReferencesAndEmptyCellsOfACountedScene) {
    const Scene scene = counted_scene();
    struct Want {
        GridAssign assign;
        size_t refs, non_empty;
    };
    for (const Want& w : {Want{GridAssign::Clip, 1 + 13 + 1, 15}, Want{GridAssign::Bounds, 1 + 16 + 1, 17}}) {
        const Grid<Triangles<>> grid(Triangles<>(scene.mesh), grid_options(4, w.assign));
        const GridData& d = grid.data();
        ASSERT_EQ(d.frame.res, (std::array<uint32_t, 3>{4, 4, 4}));
        EXPECT_EQ(d.lists.refs.size(), w.refs);
        EXPECT_EQ(d.lists.start.size(), 65u) << "one offset per cell plus the end";
        const AccelStats s = grid.stats();
        EXPECT_EQ(s.nodes, 64u);
        EXPECT_EQ(s.leaves, w.non_empty) << "leaves are the non-empty cells";
        EXPECT_EQ(s.bytes, (65 + w.refs) * sizeof(uint32_t));
        auto extra = [&](const std::string& key) {
            for (const auto& [k, v] : s.extra)
                if (k == key) return v;
            return std::string("(missing)");
        };
        EXPECT_EQ(extra("references"), std::to_string(w.refs));
        EXPECT_EQ(extra("empty cells"), std::to_string(64 - w.non_empty) + " (" +
                                            fixed(100.0 * double(64 - w.non_empty) / 64.0, 1) + "%)");
        EXPECT_EQ(extra("references per primitive"), fixed(double(w.refs) / 3.0, 2));
        // Cell (0,0,0) holds exactly the small triangle, flagged as referenced by no other cell.
        ASSERT_EQ(d.lists.count(0), 1u);
        EXPECT_EQ(d.lists.refs[d.lists.start[0]], 0u | kSingleCell);
        // The hypotenuse corner cells (1,3,3) and (2,2,3) hold the big triangle (not flagged);
        // cell (2,3,3) only with bounds assignment.
        EXPECT_EQ(d.lists.count(d.frame.index(1, 3, 3)), 1u);
        EXPECT_EQ(d.lists.refs[d.lists.start[d.frame.index(2, 2, 3)]], 1u);
        EXPECT_EQ(d.lists.count(d.frame.index(2, 3, 3)), w.assign == GridAssign::Bounds ? 1u : 0u);
    }
}

TEST(GridCells, SahLikeCostCountsCellsAndReferences) {
    const Scene scene = counted_scene();
    const Grid<Triangles<>> grid(Triangles<>(scene.mesh), grid_options(4, GridAssign::Clip));
    // Every unit cell has area 6 of the root's 96: cost = 6/96 * (64 cells + 15 references).
    EXPECT_NEAR(grid.stats().sah_cost, 6.0 / 96.0 * (64 + 15), 1e-9);
}

/// Every primitive that touches a cell's closed box is in that cell's list; with clip
/// assignment, every listed primitive touches the cell widened by eps.
template <class Prims>
void expect_exact_cells(const Prims& prims, const GridFrame& f, const CellLists& lists, size_t first,
                        const std::vector<uint32_t>& candidates, GridAssign assign) {
    for (uint32_t z = 0; z < f.res[2]; ++z)
        for (uint32_t y = 0; y < f.res[1]; ++y)
            for (uint32_t x = 0; x < f.res[0]; ++x) {
                const size_t c = first + f.index(x, y, z);
                std::set<uint32_t> listed;
                for (uint32_t k = lists.start[c]; k < lists.start[c + 1]; ++k) listed.insert(lists.refs[k] & kPrimMask);
                ASSERT_EQ(listed.size(), lists.count(c)) << "a primitive listed twice in one cell";
                const Aabb box = f.cell_box(x, y, z);
                const Aabb wide{box.min - f.eps, box.max + f.eps};
                for (uint32_t id : candidates) {
                    const Aabb b = prims.bounds(id);
                    if (intersection(b, wide).empty()) {  // cannot touch: skip the costly clips
                        ASSERT_FALSE(listed.count(id)) << "prim " << id << " listed in far cell " << c;
                        continue;
                    }
                    const bool touches = !clipped_bounds(prims, id, box).empty();
                    const bool near = !clipped_bounds(prims, id, wide).empty();
                    if (touches) {
                        ASSERT_TRUE(listed.count(id)) << "prim " << id << " missing from cell " << c;
                    }
                    if (assign == GridAssign::Clip && listed.count(id)) {
                        ASSERT_TRUE(near) << "prim " << id << " listed in cell " << c << " it does not touch";
                    }
                }
            }
}

TEST(GridCells, ClipAssignmentIsExactAndBoundsAssignmentComplete) {
    const Scene& scene = nasty("soup");
    const Triangles<> prims(scene.mesh);
    std::vector<uint32_t> all(prims.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    for (GridAssign assign : {GridAssign::Clip, GridAssign::Bounds}) {
        const Grid<Triangles<>> grid(prims, grid_options(12, assign));
        expect_exact_cells(prims, grid.data().frame, grid.data().lists, 0, all, assign);
    }
    const Grid<Triangles<>> clip(prims, grid_options(12, GridAssign::Clip));
    const Grid<Triangles<>> bounds(prims, grid_options(12, GridAssign::Bounds));
    EXPECT_LT(clip.data().lists.refs.size(), bounds.data().lists.refs.size()) << "clipping saves references";
}

TEST(GridCells, SubGridsAreExactAndSizedByTheDensityRule) {
    const Scene& scene = nasty("soup");
    const Triangles<> prims(scene.mesh);
    Grid2Options o;
    o.top_density = 0.5;
    o.leaf_density = 2.0;
    const TwoLevelGrid<Triangles<>> grid(prims, o);
    const Grid2Data& g = grid.data();
    std::vector<uint32_t> all(prims.size());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    // The top level's figures follow the rule on the whole scene.
    EXPECT_EQ(g.frame.res, density_resolution(g.box.extent(), 0.5 * 2000, kMaxGridCells, kMaxGridCells).n);
    size_t non_empty = 0, leaf_cells = 0;
    uint32_t cell[3];
    for (cell[2] = 0; cell[2] < g.frame.res[2]; ++cell[2])
        for (cell[1] = 0; cell[1] < g.frame.res[1]; ++cell[1])
            for (cell[0] = 0; cell[0] < g.frame.res[0]; ++cell[0]) {
                const TopCell& tc = g.top[g.frame.index(cell[0], cell[1], cell[2])];
                const Aabb box = g.frame.cell_box(cell[0], cell[1], cell[2]);
                // Which primitives touch this top cell (widened as the build does).
                std::vector<uint32_t> members;
                const Aabb wide{box.min - g.frame.eps, box.max + g.frame.eps};
                for (uint32_t id : all)
                    if (!intersection(prims.bounds(id), wide).empty() && !clipped_bounds(prims, id, wide).empty())
                        members.push_back(id);
                if (tc.empty()) {
                    EXPECT_TRUE(members.empty());
                    continue;
                }
                ++non_empty;
                const GridFrame sub = g.sub_frame(cell, tc);
                EXPECT_EQ(sub.res, density_resolution(box.extent(), 2.0 * double(members.size()), kMaxSubGridRes,
                                                      kMaxGridCells)
                                       .n);
                EXPECT_EQ(tc.first_leaf, leaf_cells) << "sub-grids are stored one after another";
                leaf_cells += sub.cells();
                expect_exact_cells(prims, sub, g.leaves, tc.first_leaf, members, GridAssign::Clip);
            }
    EXPECT_GT(non_empty, 1u);
    EXPECT_EQ(g.leaves.cells(), leaf_cells);
    EXPECT_EQ(grid.stats().nodes, g.frame.cells() + leaf_cells);
}

// ---- mailbox ---------------------------------------------------------------------------------

TEST(GridMailbox, RemembersEveryIdAcrossGrowth) {
    RayMailbox mb;
    std::mt19937 rng(3);
    std::vector<uint32_t> ids(2000);
    for (uint32_t& id : ids) id = rng() & kPrimMask;
    std::set<uint32_t> seen;
    for (int round = 0; round < 2; ++round)
        for (uint32_t id : ids) {
            const bool fresh = seen.insert(id).second;
            ASSERT_EQ(mb.first_visit(id), fresh) << "id " << id << " round " << round;
        }
    EXPECT_EQ(mb.size(), seen.size());
}

/// Triangles that log every primitive test, to see what a query tested.
class LoggedTriangles {
public:
    LoggedTriangles(const TriangleMesh& mesh, std::vector<uint32_t>* log) : tris_(mesh), log_(log) {}
    size_t size() const { return tris_.size(); }
    size_t bytes() const { return tris_.bytes(); }
    Aabb bounds(uint32_t i) const { return tris_.bounds(i); }
    Vec3 centroid(uint32_t i) const { return tris_.centroid(i); }
    std::array<Vec3, 3> triangle(uint32_t i) const { return tris_.triangle(i); }
    Aabb clip(uint32_t i, const Aabb& box) const { return tris_.clip(i, box); }
    bool intersect(uint32_t i, const Ray& r, Hit& h) const { return log_->push_back(i), tris_.intersect(i, r, h); }
    bool occludes(uint32_t i, const Ray& r) const { return log_->push_back(i), tris_.occludes(i, r); }

private:
    Triangles<> tris_;
    std::vector<uint32_t>* log_;
};

/// Largest number of times one primitive was tested by one query, over the conformance rays;
/// also checks that the counters count exactly the tests made and the hits match brute force.
template <class Accel>
size_t most_tests_of_one_primitive(const Accel& accel, const Scene& scene, std::vector<uint32_t>& log) {
    const BruteForce<Triangles<>> brute{Triangles<>(scene.mesh)};
    const testing::PrimitiveProbe probe(scene, "moller");
    size_t most = 0;
    for (const Ray& ray : testing::conformance_rays(scene, 600, 9)) {
        for (int any = 0; any < 2; ++any) {
            log.clear();
            RayCounters c;
            if (any) {
                EXPECT_EQ(accel.any(ray, c), brute.occluded(ray));
            } else {
                EXPECT_TRUE(testing::same_closest_hit(accel.closest(ray, c), brute.intersect(ray), ray, probe));
            }
            EXPECT_EQ(c.prims, log.size());
            std::sort(log.begin(), log.end());
            for (size_t i = 0; i < log.size();) {
                size_t j = i;
                while (j < log.size() && log[j] == log[i]) ++j;
                most = std::max(most, j - i);
                i = j;
            }
        }
    }
    return most;
}

TEST(GridMailbox, OnTestsEachPrimitiveOnceOffRetestsShared) {
    // Big overlapping triangles through one point: each spans many cells.
    const Scene& scene = nasty("same-centroid");
    std::vector<uint32_t> log;
    for (bool mailbox : {true, false}) {
        SCOPED_TRACE(mailbox ? "mailbox=on" : "mailbox=off");
        GridOptions o;
        o.mailbox = mailbox;
        const Grid<LoggedTriangles> grid(LoggedTriangles(scene.mesh, &log), o);
        const size_t grid_most = most_tests_of_one_primitive(grid, scene, log);
        Grid2Options o2;
        o2.mailbox = mailbox;
        const TwoLevelGrid<LoggedTriangles> grid2(LoggedTriangles(scene.mesh, &log), o2);
        const size_t grid2_most = most_tests_of_one_primitive(grid2, scene, log);
        if (mailbox) {
            EXPECT_EQ(grid_most, 1u);
            EXPECT_EQ(grid2_most, 1u);
        } else {
            EXPECT_GT(grid_most, 1u) << "without the mailbox a shared primitive is re-tested";
            EXPECT_GT(grid2_most, 1u);
        }
    }
}

TEST(GridMailbox, OffStillAgreesWithBruteForceOnEveryNastyScene) {
    for (const Scene& scene : testing::nasty_scenes())
        for (const char* spec : {"grid:mailbox=off", "grid2:mailbox=off", "grid:mailbox=off,assign=bounds,lambda=16"}) {
            SCOPED_TRACE(std::string(spec) + " on " + scene.name);
            const auto& ref = testing::reference_for("nasty:" + scene.name, scene, "moller", 3000);
            EXPECT_EQ(testing::compare_with_reference(*build_accel(spec, scene), ref, scene.name), "");
        }
}

// ---- traversal edge cases --------------------------------------------------------------------

TEST(GridTraversal, EmptySceneAndOnePrimitive) {
    const Scene empty;
    for (const char* spec : {"grid", "grid2"}) {
        auto accel = build_accel(spec, empty);
        EXPECT_TRUE(accel->bounds().empty());
        EXPECT_FALSE(accel->intersect({{0, 0, -1}, 0, {0, 0, 1}, kInfinity}).found());
        EXPECT_FALSE(accel->occluded({{0, 0, -1}, 0, {0, 0, 1}, kInfinity}));
        EXPECT_EQ(accel->stats().nodes, 0u);
        auto one = build_accel(spec, nasty("one-triangle"));
        // grid: 5 cells wanted on a flat box, sqrt(5) rounds to 2 x 2 x 1; grid2: 1 top cell, 1 sub-cell.
        EXPECT_EQ(one->stats().nodes, std::string(spec) == "grid" ? 4u : 2u);
        const Hit h = one->intersect({{0.25f, 0.25f, 1}, 0, {0, 0, -1}, kInfinity});
        EXPECT_EQ(h.prim, 0u);
        EXPECT_EQ(h.t, 1.0f);
    }
}

TEST(GridTraversal, InvalidRaysAreMissesNotHangs) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Scene& scene = nasty("soup");
    const BruteForce<Triangles<>> brute{Triangles<>(scene.mesh)};
    const testing::PrimitiveProbe probe(scene, "moller");
    const std::vector<Ray> rays = {
        {{nan, 0, 0}, 0, {1, 0, 0}, kInfinity},   {{-3, 0, 0}, 0, {nan, 0, 0}, kInfinity},
        {{-3, 0, 0}, 0, {0, 0, 0}, kInfinity},     {{0, 0, 0}, 0, {0, 0, 0}, kInfinity},
        {{-3, 0, 0}, 0, {1, 0, 0}, nan},           {{-3, 0, 0}, 2, {1, 0, 0}, 1},
        {{-3, 0, 0}, 0, {1e-40f, 1e-40f, 1e-40f}, kInfinity},
        {{kInfinity, 0, 0}, 0, {-1, 0, 0}, kInfinity}, {{0, 0, 0}, 0, {kInfinity, 0, 0}, kInfinity},
        {{0, 0, 0}, -kInfinity, {1, 1, 1}, kInfinity},
    };
    for (const char* spec : {"grid", "grid2", "grid:mailbox=off"}) {
        auto accel = build_accel(spec, scene);
        for (const Ray& r : rays) {
            EXPECT_TRUE(testing::same_closest_hit(accel->intersect(r), brute.intersect(r), r, probe)) << spec;
            EXPECT_EQ(accel->occluded(r), brute.occluded(r)) << spec;
        }
    }
}

/// A floor tessellated on exactly the grid's planes, and rays along those planes (origins on
/// cell boundaries, +0/-0 components), starting inside, on the boundary, and at the corners.
TEST(GridTraversal, RaysAlongCellPlanesAndFromTheBoundary) {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) {
            const Vec3 p(float(i), 0, float(j));
            add_triangle(m, p, p + Vec3(1, 0, 0), p + Vec3(1, 0, 1));
            add_triangle(m, p, p + Vec3(1, 0, 1), p + Vec3(0, 0, 1));
            add_triangle(m, p + Vec3(0, 8, 0), p + Vec3(1, 8, 1), p + Vec3(1, 8, 0));  // a ceiling at y = 8
        }
    Scene scene;
    scene.name = "planes";
    scene.mesh = std::move(m);
    const BruteForce<Triangles<>> brute{Triangles<>(scene.mesh)};
    const testing::PrimitiveProbe probe(scene, "moller");
    std::vector<Ray> rays;
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j)
            for (float zero : {0.0f, -0.0f}) {
                const float x = float(i), z = float(j);
                rays.push_back({{x, 4, z}, 0, {zero, -1, zero}, kInfinity});    // down through a vertex
                rays.push_back({{x, 4, z}, 0, {zero, 1, zero}, kInfinity});     // up
                rays.push_back({{x, 8, z}, 0, {zero, -1, zero}, kInfinity});    // from the boundary
                rays.push_back({{x, 0, z}, 0, {1, zero, zero}, kInfinity});     // in the floor's plane
                rays.push_back({{-1, 0.5f, z}, 0, {1, zero, zero}, kInfinity}); // along a row of cells
                rays.push_back({{x, 4, z}, 0, {0.5f, -1, 0.5f}, 3.9f});         // stops short of the floor
                rays.push_back({{x, 4, z}, 0, {0.5f, -1, 0.5f}, 4.0f});         // reaches it exactly
            }
    rays.push_back({{0, 8, 0}, 0, {1, -1, 1}, kInfinity});  // from a corner of the box
    rays.push_back({{8, 0, 8}, 0, {-1, 1, -1}, kInfinity});
    for (const char* spec : {"grid:res=8", "grid:res=16,assign=bounds", "grid", "grid2", "grid2:top=64,leaf=64"}) {
        auto accel = build_accel(spec, scene);
        for (const Ray& r : rays) {
            ASSERT_TRUE(testing::same_closest_hit(accel->intersect(r), brute.intersect(r), r, probe))
                << spec << " ray from (" << r.org.x << "," << r.org.y << "," << r.org.z << ") dir (" << r.dir.x << ","
                << r.dir.y << "," << r.dir.z << ")";
            ASSERT_EQ(accel->occluded(r), brute.occluded(r)) << spec;
        }
    }
}

TEST(GridTraversal, HitBeyondTheCurrentCellDoesNotEndTheWalk) {
    // A slanted triangle in the plane z = 0.9 - 0.05 x runs alongside the ray from x = 0 and
    // crosses it at x = 8: it is met in the first cell, with its hit seven cells further on. A wall
    // at x = 4, in between, must still win.
    TriangleMesh m;
    add_triangle(m, {0, 0, 0.9f}, {0, 1, 0.9f}, {10, 0.5f, 0.4f});
    add_triangle(m, {4, -1, -1}, {4, 3, -1}, {4, -1, 3});
    Scene scene;
    scene.name = "beyond";
    scene.mesh = std::move(m);
    const Ray ray{{0, 0.5f, 0.5f}, 0, {1, 0, 0}, kInfinity};
    const BruteForce<Triangles<>> brute{Triangles<>(scene.mesh)};
    const Hit want = brute.intersect(ray);
    ASSERT_EQ(want.prim, 1u);
    ASSERT_TRUE(brute.intersect({ray.org, 4.5f, ray.dir, kInfinity}).prim == 0u) << "the slanted one lies behind";
    for (const char* spec : {"grid:res=10", "grid:res=3", "grid2:top=1,leaf=1024"}) {
        auto accel = build_accel(spec, scene);
        RayCounters c;
        const Hit got = accel->intersect(ray, c);
        EXPECT_EQ(got.prim, want.prim) << spec;
        EXPECT_EQ(got.t, want.t) << spec;
        EXPECT_GE(c.prims, 2u) << spec;
    }
}

}  // namespace
}  // namespace thicket::grid_test
