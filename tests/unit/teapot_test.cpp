// The built-in Utah teapot: the data (counts, groups, shared borders, collapsed edges, extents,
// the shared tessellated teapot.ply), and the Bezier kernel on it (no cracks at shared borders,
// finite normals at the poles, the hit mask of a fine tessellation).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include "bezier_reference.h"
#include "thicket/bvh/bvh.h"
#include "thicket/core/error.h"
#include "thicket/prims/teapot_patches.h"
#include "thicket/prims/triangles.h"

namespace thicket::teapot_test {
namespace {

using testing::dv;

/// The four border curves of a patch as control point quadruples: v = 0, u = 1, v = 1, u = 0.
std::array<std::array<Vec3, 4>, 4> borders(const BezierPatch& p) {
    std::array<std::array<Vec3, 4>, 4> b;
    for (int k = 0; k < 4; ++k) {
        b[0][k] = p.control_point(k, 0);
        b[1][k] = p.control_point(3, k);
        b[2][k] = p.control_point(k, 3);
        b[3][k] = p.control_point(0, k);
    }
    return b;
}

bool same_curve(const std::array<Vec3, 4>& a, const std::array<Vec3, 4>& b) {
    bool forward = true, backward = true;
    for (int k = 0; k < 4; ++k) {
        forward = forward && a[k] == b[k];
        backward = backward && a[k] == b[3 - k];
    }
    return forward || backward;
}

bool collapsed(const std::array<Vec3, 4>& a) { return a[0] == a[1] && a[1] == a[2] && a[2] == a[3]; }

TEST(Teapot, NewellDataCountsAndGroups) {
    ASSERT_EQ(teapot_newell_patches().size(), 32u);
    ASSERT_EQ(teapot_newell_vertices().size(), 306u);
    std::set<int> used;
    for (const auto& patch : teapot_newell_patches())
        for (int i : patch) {
            ASSERT_GE(i, 1);
            ASSERT_LE(i, 306);
            used.insert(i);
        }
    // Every vertex but the lid's four near-apex duplicates is used.
    EXPECT_EQ(used.size(), 302u);
    for (int unused : {205, 206, 216, 223}) EXPECT_FALSE(used.count(unused)) << unused;
    // Spot checks of the published table: the first and last vertex, the knob, the spout tip.
    EXPECT_EQ(teapot_newell_vertices()[0], Vec3(1.4f, 0.0f, 2.4f));
    EXPECT_EQ(teapot_newell_vertices()[305], Vec3(1.425f, -0.798f, 0.0f));
    EXPECT_EQ(teapot_newell_vertices()[203], Vec3(0.0f, 0.0f, 3.15f));
    EXPECT_EQ(teapot_newell_vertices()[187], Vec3(3.525f, -0.25f, 2.49375f));

    std::map<TeapotGroup, int> count;
    for (int p = 0; p < 32; ++p) ++count[teapot_group(p)];
    EXPECT_EQ(count[TeapotGroup::Rim], 4);
    EXPECT_EQ(count[TeapotGroup::Body], 8);
    EXPECT_EQ(count[TeapotGroup::Handle], 4);
    EXPECT_EQ(count[TeapotGroup::Spout], 4);
    EXPECT_EQ(count[TeapotGroup::Lid], 8);
    EXPECT_EQ(count[TeapotGroup::Bottom], 4);
    EXPECT_STREQ(teapot_group_name(TeapotGroup::Spout), "spout");
    EXPECT_THROW(teapot_group(32), Error);
}

TEST(Teapot, PatchesJoinAtSharedBordersWithIdenticalControlPoints) {
    // Each of the 128 borders is collapsed to a point (lid knob, bottom centre), shared with
    // exactly one other patch (identical control points, so the surfaces meet exactly: C0), or
    // one of the 16 open borders: rim lip, handle and spout ends (they enter the body) and the
    // lid's lower edge (the lid rests in the rim).
    const std::vector<BezierPatch> patches = teapot_patches();
    int shared = 0, open = 0, points = 0;
    std::map<TeapotGroup, int> open_by_group;
    for (int a = 0; a < 32; ++a)
        for (int e = 0; e < 4; ++e) {
            const auto curve = borders(patches[a])[e];
            if (collapsed(curve)) {
                ++points;
                EXPECT_TRUE(teapot_group(a) == TeapotGroup::Lid || teapot_group(a) == TeapotGroup::Bottom) << a;
                continue;
            }
            int partners = 0;
            for (int b = 0; b < 32; ++b)
                for (int f = 0; f < 4 && b != a; ++f) partners += same_curve(curve, borders(patches[b])[f]);
            EXPECT_LE(partners, 1) << "patch " << a << " border " << e;
            if (partners == 1)
                ++shared;
            else
                ++open, ++open_by_group[teapot_group(a)];
        }
    EXPECT_EQ(points, 8);
    EXPECT_EQ(shared, 104);
    EXPECT_EQ(open, 16);
    EXPECT_EQ(open_by_group[TeapotGroup::Rim], 4);
    EXPECT_EQ(open_by_group[TeapotGroup::Handle], 4);
    EXPECT_EQ(open_by_group[TeapotGroup::Spout], 4);
    EXPECT_EQ(open_by_group[TeapotGroup::Lid], 4);
    EXPECT_EQ(open_by_group[TeapotGroup::Body], 0) << "the body joins the rim above and the bottom below";
}

TEST(Teapot, CollapsedEdgesAreTheKnobAndTheBottomCentre) {
    const std::vector<BezierPatch> patches = teapot_patches();
    for (int p = 20; p < 24; ++p)
        for (int i = 0; i < 4; ++i) EXPECT_EQ(patches[p].control_point(i, 0), Vec3(0.0f, 3.15f, -0.0f)) << p;
    for (int p = 28; p < 32; ++p)
        for (int i = 0; i < 4; ++i) EXPECT_EQ(patches[p].control_point(i, 0), Vec3(0.0f, 0.0f, -0.0f)) << p;
}

TEST(Teapot, SurfaceExtentsMatchTheKnownTeapot) {
    // y-up: x from the handle (-3) to the spout tip (3.434), y from the bottom (0) to the
    // knob (3.15), z within the body's radius 2. The control points reach further (3.525).
    Aabb surface;
    for (const BezierPatch& p : teapot_patches())
        for (int j = 0; j <= 64; ++j)
            for (int i = 0; i <= 64; ++i) surface.grow(p.point(i / 64.0f, j / 64.0f));
    EXPECT_NEAR(surface.min.x, -3.0f, 1e-4f);
    EXPECT_NEAR(surface.max.x, 3.434f, 1e-3f);
    EXPECT_NEAR(surface.min.y, 0.0f, 1e-6f);
    EXPECT_NEAR(surface.max.y, 3.15f, 1e-6f);
    EXPECT_NEAR(surface.min.z, -2.0f, 1e-4f);
    EXPECT_NEAR(surface.max.z, 2.0f, 1e-4f);
    Aabb control;
    for (const BezierPatch& p : teapot_patches()) control.grow(p.bounds());
    EXPECT_NEAR(control.max.x, 3.525f, 1e-6f);
}

/// Reads the vertices of a PLY in the shared scenes' layout (binary, float x y z first).
std::vector<Vec3> read_ply_vertices(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    size_t count = 0;
    while (std::getline(in, line) && line != "end_header")
        if (line.rfind("element vertex ", 0) == 0) count = std::stoul(line.substr(15));
    std::vector<Vec3> v(count);
    in.read(reinterpret_cast<char*>(v.data()), std::streamsize(count * sizeof(Vec3)));
    if (!in) v.clear();
    return v;
}

TEST(Teapot, AgreesWithTheSharedTessellatedTeapot) {
    // teapot.ply (a tessellation of Newell's data from another source, y-up) has vertices at
    // every patch's corners and centre: a control point typed wrong would move one of them.
    const std::string path = THICKET_SHARED_SCENES "/teapot.ply";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not found";
    const std::vector<Vec3> ply = read_ply_vertices(path);
    ASSERT_EQ(ply.size(), 3644u);
    const std::vector<BezierPatch> patches = teapot_patches();
    for (int p = 0; p < 32; ++p)
        for (float u : {0.0f, 0.5f, 1.0f})
            for (float v : {0.0f, 0.5f, 1.0f}) {
                const Vec3 q = patches[p].point(u, v);
                float best = kInfinity;
                // The y-up teapot is symmetric under z -> -z: either sign convention matches.
                for (const Vec3& w : ply) best = std::min(best, length(w - q));
                EXPECT_LT(best, 1e-5f) << "patch " << p << " at (" << u << ", " << v << ")";
            }
}

TEST(Teapot, NormalsPointOutward) {
    // Horizontal rays at the body from outside: the first hit's normal faces the ray.
    const std::vector<BezierPatch> patches = teapot_patches();
    int checked = 0;
    for (int k = 0; k < 72; ++k) {
        const float a = float(k) * 0.0872665f + 0.3f;  // 5 degrees apart, away from spout and handle
        const Vec3 dir{-std::cos(a), 0.0f, -std::sin(a)};
        for (float y : {0.5f, 1.2f, 2.0f}) {
            const Ray ray{Vec3(0, y, 0) - dir * 10.0f, 0, dir, kInfinity};
            ShapeHit h;
            const int p = testing::closest_patch(patches, ray, h);
            ASSERT_GE(p, 0);
            if (teapot_group(p) != TeapotGroup::Body) continue;  // handle or spout in front
            EXPECT_LT(dot(patches[p].normal(ray.org + dir * h.t, h.u, h.v), dir), -0.5f) << k << " " << y;
            ++checked;
        }
    }
    EXPECT_GT(checked, 150);
    // From above the lid, and from below the bottom.
    ShapeHit h;
    const Ray down{{0.3f, 10, 0.2f}, 0, {0, -1, 0}, kInfinity}, up{{0.3f, -10, 0.2f}, 0, {0, 1, 0}, kInfinity};
    int p = testing::closest_patch(patches, down, h);
    ASSERT_EQ(teapot_group(p), TeapotGroup::Lid);
    EXPECT_GT(patches[p].normal({}, h.u, h.v).y, 0.0f);
    p = testing::closest_patch(patches, up, h);
    ASSERT_EQ(teapot_group(p), TeapotGroup::Bottom);
    EXPECT_LT(patches[p].normal({}, h.u, h.v).y, 0.0f);
}

TEST(Teapot, PolesHaveFiniteNormals) {
    const std::vector<BezierPatch> patches = teapot_patches();
    for (int p = 20; p < 32; ++p) {
        if (p >= 24 && p < 28) continue;  // the lid's lower ring has no pole
        const float expect = p < 24 ? 1.0f : -1.0f;
        for (float u : {0.0f, 0.1f, 0.5f, 0.9f, 1.0f}) {
            const Vec3 n = patches[p].normal(patches[p].point(u, 0), u, 0.0f);
            ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << p << " " << u;
            EXPECT_NEAR(length(n), 1.0f, 1e-5f);
            EXPECT_NEAR(n.y, expect, 1e-4f) << "patch " << p << " u " << u << ": the axis";
        }
    }
    // Rays down the axis hit the knob's apex and the bottom's centre exactly.
    ShapeHit h;
    const Ray down{{0, 10, 0}, 0, {0, -1, 0}, kInfinity}, up{{0, -10, 0}, 0, {0, 1, 0}, kInfinity};
    int p = testing::closest_patch(patches, down, h);
    ASSERT_GE(p, 20);
    EXPECT_NEAR(h.t, 10 - 3.15f, 1e-5f);
    Vec3 n = patches[p].normal({0, 3.15f, 0}, h.u, h.v);
    EXPECT_NEAR(n.y, 1.0f, 1e-4f);
    p = testing::closest_patch(patches, up, h);
    ASSERT_GE(p, 28);
    EXPECT_NEAR(h.t, 10.0f, 1e-5f);
    n = patches[p].normal({0, 0, 0}, h.u, h.v);
    EXPECT_NEAR(n.y, -1.0f, 1e-4f);
}

TEST(Teapot, RaysThroughSharedBordersNeverSlipThrough) {
    // Aim at points on the borders two patches share (and at their corners, where up to four
    // patches meet) from random directions, grazing ones included: some patch must be hit at or
    // before the point. (Open borders are left out: a float ray aimed at one may pass just
    // outside it and rightly miss.)
    const std::vector<BezierPatch> patches = teapot_patches();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0, 1);
    std::normal_distribution<float> g;
    int rays = 0;
    for (int p = 0; p < 32; ++p) {
        bool shared[4] = {false, false, false, false};
        for (int e = 0; e < 4; ++e)
            for (int b = 0; b < 32; ++b)
                for (int f = 0; f < 4 && b != p; ++f) shared[e] = shared[e] || same_curve(borders(patches[p])[e], borders(patches[b])[f]);
        for (int edge = 0; edge < 4; ++edge) {
            if (!shared[edge]) continue;
            for (int k = 0; k < 25; ++k) {
                // Both ends first, where up to four patches meet, unless the other border
                // through that corner is open.
                const float s = k < 2 ? float(k) : unit(rng);
                const float u = edge == 1 ? 1.0f : (edge == 3 ? 0.0f : s);
                const float v = edge == 0 ? 0.0f : (edge == 2 ? 1.0f : s);
                const bool on[4] = {v == 0.0f, u == 1.0f, v == 1.0f, u == 0.0f};
                bool open_corner = false;
                for (int e = 0; e < 4; ++e) open_corner = open_corner || (on[e] && !shared[e]);
                if (open_corner) continue;
                const testing::DV q = testing::ref_eval(patches[p], u, v).p;
                Vec3 dir{g(rng), g(rng), g(rng)};
                dir = dir / length(dir);
                const Vec3 target{float(q.x), float(q.y), float(q.z)};
                const Ray ray{target - dir * 5.0f, 0, dir, kInfinity};
                const double t_known = testing::ddot(q - dv(ray.org), dv(dir));
                ShapeHit h;
                const int hit = testing::closest_patch(patches, ray, h);
                ASSERT_GE(hit, 0) << "slipped through patch " << p << " at (" << u << ", " << v << ")";
                EXPECT_LE(h.t, t_known + 1e-4) << "patch " << p << " at (" << u << ", " << v << ")";
                ++rays;
            }
        }
    }
    EXPECT_GT(rays, 104 * 23);
}

TEST(Teapot, HitMaskMatchesAFineTessellationAndHitsLieOnTheSurface) {
    // 64 x 64 quads per patch in double, rounded to float triangles; its hit mask over four
    // views must match the kernel's on >= 99.5% of the pixels (differences only along
    // silhouettes, where the tessellation cuts corners), and every kernel hit lies on the
    // surface within 1e-4 of the scene size.
    const std::vector<BezierPatch> patches = teapot_patches();
    TriangleMesh mesh;
    const int n = 64;
    for (const BezierPatch& p : patches) {
        const uint32_t base = uint32_t(mesh.positions.size());
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const testing::DV q = testing::ref_eval(p, double(i) / n, double(j) / n).p;
                mesh.positions.push_back({float(q.x), float(q.y), float(q.z)});
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const uint32_t a = base + j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
                mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
            }
    }
    const Bvh<Triangles<TriangleTest::Watertight>> bvh(Triangles<TriangleTest::Watertight>(mesh), BvhBuildOptions{});
    const float scene = length(Vec3(6.434f, 3.15f, 4.0f));
    const int res = 100;
    int pixels = 0, agree = 0, hits = 0;
    const Vec3 eyes[4] = {{0, 2, 9}, {8, 5, 3}, {-6, -3, -6}, {0.5f, 9, 0.3f}};
    for (const Vec3& eye : eyes) {
        const Vec3 at{0.2f, 1.5f, 0}, fwd = normalize(at - eye);
        const Vec3 right = normalize(cross(fwd, Vec3(0.01f, 1, 0.02f))), up = cross(right, fwd);
        for (int y = 0; y < res; ++y)
            for (int x = 0; x < res; ++x) {
                const float sx = (x + 0.5f) / res * 2 - 1, sy = (y + 0.5f) / res * 2 - 1;
                const Ray ray{eye, 0, normalize(fwd + right * (0.45f * sx) + up * (0.45f * sy)), kInfinity};
                ShapeHit h;
                const int p = testing::closest_patch(patches, ray, h);
                NoCounters none;
                const bool tess = bvh.closest(ray, none).found();
                ++pixels;
                agree += (p >= 0) == tess;
                if (p >= 0) {
                    ++hits;
                    ASSERT_LT(testing::hit_residual(patches[p], ray, h), 1e-4 * scene);
                    const Vec3 nrm = patches[p].normal(ray.org + ray.dir * h.t, h.u, h.v);
                    ASSERT_TRUE(std::isfinite(nrm.x) && std::fabs(length(nrm) - 1) < 1e-4f);
                }
            }
    }
    EXPECT_GT(hits, pixels / 8);
    EXPECT_GE(double(agree) / pixels, 0.995) << pixels - agree << " of " << pixels << " pixels differ";
    std::printf("teapot mask: %d of %d pixels agree with the 64x64-per-patch tessellation, %d hits\n", agree, pixels, hits);
}

}  // namespace
}  // namespace thicket::teapot_test
