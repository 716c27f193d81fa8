// The Bezier patch kernel against a double-precision reference (bezier_reference.h): first roots,
// grazing rays, collapsed edges, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "bezier_reference.h"
#include "thicket/core/error.h"
#include "thicket/prims/bezier.h"

namespace thicket::bezier_test {
namespace {

using testing::DV;
using testing::dv;

BezierPatch flat_patch() {
    // Evenly spaced control points: P(u, v) = (2u, 2v, 0) exactly (linear precision).
    BezierPatch::ControlPoints cp;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) cp[4 * j + i] = {2.0f * i / 3.0f, 2.0f * j / 3.0f, 0.0f};
    return BezierPatch(cp);
}

/// A saddle-and-bump patch that folds over itself as seen from most directions.
BezierPatch wavy_patch() {
    BezierPatch::ControlPoints cp;
    const float h[4][4] = {{0, 1.5f, -1, 0.5f}, {1, -2, 2.5f, -0.5f}, {-1, 2, -2, 1}, {0.5f, -1, 1.5f, 0}};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) cp[4 * j + i] = {float(i) + 0.3f * float(j), float(j), h[j][i]};
    return BezierPatch(cp);
}

/// Half of a cylinder-like surface curling back over itself (a fold seen from the side).
BezierPatch curl_patch() {
    BezierPatch::ControlPoints cp;
    const float xs[4] = {0, 2, 2, 0}, zs[4] = {0, 0, 1.5f, 1.5f};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) cp[4 * j + i] = {xs[i], float(j), zs[i] + 0.2f * float(i * j) / 9.0f};
    return BezierPatch(cp);
}

Vec3 random_unit(std::mt19937& rng) {
    std::normal_distribution<float> g;
    for (;;) {
        const Vec3 v{g(rng), g(rng), g(rng)};
        const float l = length(v);
        if (l > 1e-3f) return v / l;
    }
}

double patch_size(const BezierPatch& p) { return max_component(p.bounds().extent()); }

TEST(Bezier, FlatPatchGivesExactDistanceAndParameters) {
    const BezierPatch patch = flat_patch();
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> in(0.01f, 0.99f);
    for (int k = 0; k < 200; ++k) {
        const float u = in(rng), v = in(rng);
        const float dz = k % 2 ? -1.0f : 1.0f;  // both sides
        const Ray ray{{2 * u, 2 * v, -3 * dz}, 0.0f, {0, 0, 2 * dz}, kInfinity};
        ShapeHit h;
        ASSERT_TRUE(patch.intersect(ray, ray.tmax, h)) << u << " " << v;
        EXPECT_NEAR(h.t, 1.5f, 1e-6f);
        EXPECT_NEAR(h.u, u, 1e-6f);
        EXPECT_NEAR(h.v, v, 1e-6f);
    }
    ShapeHit h;
    EXPECT_FALSE(patch.intersect({{2.5f, 1, 1}, 0, {0, 0, -1}, kInfinity}, kInfinity, h)) << "beside the patch";
    EXPECT_FALSE(patch.intersect({{1, 1, 1}, 0, {0, 0, 1}, kInfinity}, kInfinity, h)) << "behind the origin";
    EXPECT_FALSE(patch.intersect({{1, 1, 1}, 0, {0, 0, -1}, kInfinity}, 0.5f, h)) << "beyond tmax";
    EXPECT_FALSE(patch.intersect({{1, 1, 1}, 1.5f, {0, 0, -1}, kInfinity}, kInfinity, h)) << "before tmin";
    EXPECT_TRUE(patch.intersect({{1, 1, 1}, 1.0f, {0, 0, -1}, kInfinity}, 1.0f, h)) << "t == tmin == tmax";
    EXPECT_FALSE(patch.intersect({{1, 1, 1}, 0, {0, 0, 0}, kInfinity}, kInfinity, h)) << "zero direction";
    EXPECT_FALSE(patch.intersect({{NAN, 1, 1}, 0, {0, 0, -1}, kInfinity}, kInfinity, h)) << "NaN origin";
    // The normal is dP/du x dP/dv = +z, whatever the side the ray came from.
    const Vec3 n = patch.normal({1, 1, 0}, 0.5f, 0.5f);
    EXPECT_NEAR(n.z, 1.0f, 1e-6f);
}

TEST(Bezier, BordersAndCornersAreHit) {
    // Rays landing exactly on the border and the corners (the arithmetic is exact in binary),
    // straight and slanted: a ray through a border must not slip out of the patch.
    const BezierPatch patch = flat_patch();
    for (float x : {0.0f, 1.0f, 2.0f})
        for (float y : {0.0f, 0.75f, 2.0f}) {
            if (x == 1.0f && y == 0.75f) continue;  // interior
            for (const Vec3 d : {Vec3(0, 0, -1), Vec3(0.25f, -0.5f, -1), Vec3(-0.5f, 0.25f, -1)}) {
                const Ray ray{Vec3(x, y, 0) - d, 0, d, kInfinity};
                ShapeHit h;
                ASSERT_TRUE(patch.intersect(ray, kInfinity, h)) << x << " " << y;
                EXPECT_NEAR(h.t, 1.0f, 1e-6f);
                EXPECT_NEAR(h.u, x / 2, 1e-6f);
                EXPECT_NEAR(h.v, y / 2, 1e-6f);
            }
        }
}

/// Random rays at the patch: the kernel's first root is the reference's, every kernel hit is a
/// genuine surface point, and the kernel finds a hit wherever the reference does.
void compare_with_reference(const BezierPatch& patch, uint32_t seed, int rays) {
    std::mt19937 rng(seed);
    const Aabb box = patch.bounds();
    const double size = patch_size(patch);
    std::uniform_real_distribution<float> unit(0, 1);
    int hits = 0, extra = 0;
    const testing::RefGrid grid(patch, 48);
    for (int k = 0; k < rays; ++k) {
        const Vec3 target = box.min + box.extent() * Vec3(unit(rng), unit(rng), unit(rng));
        const Vec3 dir = random_unit(rng) * (0.5f + unit(rng));
        const Ray ray{target - dir * 4.0f, 0.0f, dir, kInfinity};
        ShapeHit h;
        const bool got = patch.intersect(ray, ray.tmax, h);
        const auto want = testing::ref_first_hit(patch, grid, ray, ray.tmax);
        if (got) {
            ASSERT_LT(testing::hit_residual(patch, ray, h), 1e-5 * size) << "ray " << k << ": not on the surface";
            ++hits;
        }
        if (want) {
            ASSERT_TRUE(got) << "ray " << k << ": missed the root at t = " << want->t;
            const double tol = 1e-5 * size / length(dir);
            // The kernel may find a nearer genuine root that the reference tessellation skipped
            // (a fold thinner than its triangles), never a farther one.
            EXPECT_LE(h.t, want->t + tol) << "ray " << k;
            if (h.t < want->t - tol) ++extra;
        } else if (got) {
            ++extra;
        }
    }
    EXPECT_GT(hits, rays / 10) << "the test rays should hit often";
    EXPECT_LE(extra, rays / 200) << "roots the reference did not see should be rare grazing ones";
}

TEST(Bezier, FirstRootMatchesDoublePrecisionReference) {
    compare_with_reference(wavy_patch(), 2, 1500);
    compare_with_reference(curl_patch(), 3, 1500);
}

TEST(Bezier, GrazingRaysAreNeverMissed) {
    // Rays at a small angle (1e-1 .. 1e-5) to the tangent plane at S(u, v), where Newton alone
    // fails. Rounding the ray to float moves it off S(u, v), so the root of the float ray is
    // found in double by polishing from (u, v); the kernel must hit at or before it.
    for (const BezierPatch& patch : {wavy_patch(), curl_patch()}) {
        std::mt19937 rng(4);
        std::uniform_real_distribution<float> in(0.02f, 0.98f);
        const double size = patch_size(patch);
        int checked = 0;
        for (int k = 0; k < 2000; ++k) {
            const float u = in(rng), v = in(rng);
            const testing::RefSample s = testing::ref_eval(patch, u, v);
            const DV n = testing::dcross(s.du, s.dv) * (1.0 / testing::dlen(testing::dcross(s.du, s.dv)));
            DV w = testing::dcross(n, dv(random_unit(rng)));
            w = w * (1.0 / testing::dlen(w));
            const double angle = std::pow(10.0, -1.0 - 4.0 * (k % 5) / 4.0) * (k % 2 ? 1 : -1);
            const DV d = w * std::cos(angle) + n * std::sin(angle);
            const Vec3 dir{float(d.x), float(d.y), float(d.z)};
            const DV o = s.p - d * (2.0 * size);
            const Ray ray{{float(o.x), float(o.y), float(o.z)}, 0.0f, dir, kInfinity};
            const auto root = testing::ref_polish(patch, dv(ray.org), dv(dir), {2.0 * size, u, v}, size);
            ShapeHit h;
            const bool got = patch.intersect(ray, ray.tmax, h);
            if (got) {
                EXPECT_LT(testing::hit_residual(patch, ray, h), 1e-5 * size) << "ray " << k;
            }
            if (!root || root->u < 0 || root->u > 1 || root->v < 0 || root->v > 1) continue;
            ++checked;
            ASSERT_TRUE(got) << "ray " << k << " at angle " << angle << " missed the root at t = " << root->t;
            EXPECT_LE(h.t, root->t + 1e-5 * size) << "ray " << k << " angle " << angle;
        }
        EXPECT_GT(checked, 1500) << "most float rays still cross the surface near S(u, v)";
    }
}

TEST(Bezier, ToleranceScalesWithThePatch) {
    // The same scene at 1e-6 and 1e6 times the size, and moved 1e4 patch sizes away: the same
    // hits at the same (scaled) distances. Tolerances are relative to the patch size.
    const BezierPatch base = wavy_patch();
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> unit(0, 1);
    for (const float scale : {1e-6f, 1e6f}) {
        for (const float shift : {0.0f, 1e4f}) {
            BezierPatch::ControlPoints cp = base.control_points();
            for (Vec3& c : cp) c = (c + Vec3(shift)) * scale;
            const BezierPatch scaled(cp);
            int differ = 0, hits = 0;
            for (int k = 0; k < 400; ++k) {
                const Aabb box = base.bounds();
                const Vec3 target = box.min + box.extent() * Vec3(unit(rng), unit(rng), unit(rng));
                const Vec3 dir = random_unit(rng);
                const Ray ray{target - dir * 4.0f, 0, dir, kInfinity};
                const Ray big{(ray.org + Vec3(shift)) * scale, 0, dir, kInfinity};
                ShapeHit a, b;
                const bool ha = base.intersect(ray, kInfinity, a), hb = scaled.intersect(big, kInfinity, b);
                hits += ha;
                // Moved 1e4 away, the float origin is only good to ~1e-3 of the patch.
                if (ha != hb || (ha && std::fabs(b.t / scale - a.t) > (shift > 0 ? 5e-3f : 1e-5f))) ++differ;
            }
            EXPECT_GT(hits, 100);
            EXPECT_LE(differ, 4) << "scale " << scale << " shift " << shift << ": grazing rays may flip, little else";
        }
    }
}

TEST(Bezier, CollapsedEdgeHasFiniteLimitNormal) {
    // A cone-like patch: row 0 collapsed to the apex (as the teapot's lid and bottom).
    BezierPatch::ControlPoints cp;
    const float r[4] = {0, 0.6f, 1.0f, 1.2f}, z[4] = {1, 1, 0.5f, 0};  // flat at the apex: smooth
    const float k = 0.5522847f;  // quarter circle
    for (int j = 0; j < 4; ++j) {
        const Vec3 ring[4] = {{r[j], 0, z[j]}, {r[j], r[j] * k, z[j]}, {r[j] * k, r[j], z[j]}, {0, r[j], z[j]}};
        for (int i = 0; i < 4; ++i) cp[4 * j + i] = ring[i];
    }
    const BezierPatch cone(cp);
    for (float u : {0.0f, 0.25f, 0.5f, 1.0f}) {
        const Vec3 n = cone.normal(cone.point(u, 0), u, 0.0f);
        ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << u;
        EXPECT_NEAR(length(n), 1.0f, 1e-5f);
        // At the apex of a surface of revolution the limit normal is the axis, and it agrees
        // with the normal just inside.
        const Vec3 inside = cone.normal(cone.point(u, 1e-3f), u, 1e-3f);
        EXPECT_GT(dot(n, inside), 0.999f) << "u = " << u;
        EXPECT_GT(std::fabs(n.z), 0.999f) << "the axis";
    }
    // A ray straight down the axis hits the apex itself.
    ShapeHit h;
    ASSERT_TRUE(cone.intersect({{0, 0, 3}, 0, {0, 0, -1}, kInfinity}, kInfinity, h));
    EXPECT_NEAR(h.t, 2.0f, 1e-5f);
    const Vec3 n = cone.normal({0, 0, 1}, h.u, h.v);
    EXPECT_TRUE(std::isfinite(n.x) && std::fabs(length(n) - 1) < 1e-5f);
    // Rays near the apex: hits on the surface, finite unit normals.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> off(0.0f, 0.01f);
    for (int k = 0; k < 200; ++k) {
        const Ray ray{{off(rng), off(rng), 3}, 0, {0, 0, -1}, kInfinity};
        ASSERT_TRUE(cone.intersect(ray, kInfinity, h)) << k;
        EXPECT_LT(testing::hit_residual(cone, ray, h), 1e-6);
        const Vec3 m = cone.normal(ray.org + ray.dir * h.t, h.u, h.v);
        EXPECT_NEAR(length(m), 1.0f, 1e-5f);
        EXPECT_GT(std::fabs(m.z), 0.9f);
    }
}

TEST(Bezier, PointPatchAndRaysInThePlaneEndQuickly) {
    // All 16 points equal: no area, never a crash or a hang.
    BezierPatch::ControlPoints same;
    same.fill({1, 2, 3});
    const BezierPatch point(same);
    ShapeHit h;
    BezierQueryStats stats;
    EXPECT_FALSE(intersect_counted(point, {{1, 2, 5}, 0, {0, 0, -1}, kInfinity}, kInfinity, h, stats));
    EXPECT_FALSE(BezierPatch().intersect({{0, 0, 5}, 0, {0, 0, -1}, kInfinity}, kInfinity, h));
    const Vec3 n = point.normal({1, 2, 3}, 0.5f, 0.5f);
    EXPECT_NEAR(length(n), 1.0f, 1e-6f);

    // A ray lying in the flat patch's plane: the roots form a segment. The budget bounds the work,
    // counted in subpatches (a time bound would fail on a loaded machine, not on a bug).
    const BezierPatch flat = flat_patch();
    stats = {};
    intersect_counted(flat, {{-1, 1, 0}, 0, {1, 0, 0}, kInfinity}, kInfinity, h, stats);
    EXPECT_GT(stats.subpatches, 0);
    EXPECT_LE(stats.subpatches, 4097);
}

TEST(Bezier, NonFiniteControlPointIsAnError) {
    BezierPatch::ControlPoints cp{};
    cp[7] = {0, NAN, 0};
    try {
        BezierPatch p(cp);
        FAIL() << "accepted a NaN control point";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("control point 7"), std::string::npos) << e.what();
    }
}

TEST(Bezier, EvaluationMatchesReference) {
    const BezierPatch patch = wavy_patch();
    for (float u : {0.0f, 0.3f, 1.0f})
        for (float v : {0.0f, 0.55f, 1.0f}) {
            const BezierSample s = patch.evaluate(u, v);
            const testing::RefSample r = testing::ref_eval(patch, u, v);
            EXPECT_LT(testing::dlen(dv(s.p) - r.p), 1e-5);
            EXPECT_LT(testing::dlen(dv(s.du) - r.du), 1e-4);
            EXPECT_LT(testing::dlen(dv(s.dv) - r.dv), 1e-4);
        }
    // Corners interpolate the corner control points.
    EXPECT_EQ(patch.point(0, 0), patch.control_point(0, 0));
    EXPECT_EQ(patch.point(1, 1), patch.control_point(3, 3));
}

}  // namespace
}  // namespace thicket::bezier_test
