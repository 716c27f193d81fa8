#include <gtest/gtest.h>

#include <random>

#include "thicket/core/triangle.h"

namespace thicket::triangle_test {
namespace {

template <class F>
void for_both_tests(F f) {
    f(TriangleTest::Moller, [](Vec3 a, Vec3 b, Vec3 c, const Ray& r, TriangleHit& h) {
        return intersect_moller(a, b, c, r, r.tmax, h);
    });
    f(TriangleTest::Watertight, [](Vec3 a, Vec3 b, Vec3 c, const Ray& r, TriangleHit& h) {
        return intersect_watertight(a, b, c, r, r.tmax, h);
    });
}

const Vec3 A{0, 0, 0}, B{1, 0, 0}, C{0, 1, 0};

TEST(Triangle, HitDistanceAndBarycentrics) {
    for_both_tests([](TriangleTest, auto test) {
        TriangleHit h{};
        ASSERT_TRUE(test(A, B, C, Ray{{0.25f, 0.5f, 2}, 0, {0, 0, -2}, kInfinity}, h));
        EXPECT_FLOAT_EQ(h.t, 1.0f) << "t is in units of the direction's length";
        EXPECT_FLOAT_EQ(h.u, 0.25f) << "u is the weight of v1";
        EXPECT_FLOAT_EQ(h.v, 0.5f) << "v is the weight of v2";
        // Both windings, both sides.
        ASSERT_TRUE(test(A, C, B, Ray{{0.25f, 0.5f, -2}, 0, {0, 0, 1}, kInfinity}, h));
        EXPECT_FLOAT_EQ(h.t, 2.0f);
    });
}

TEST(Triangle, MissesAndInterval) {
    for_both_tests([](TriangleTest, auto test) {
        TriangleHit h{};
        EXPECT_FALSE(test(A, B, C, Ray{{0.6f, 0.6f, 1}, 0, {0, 0, -1}, kInfinity}, h)) << "outside the hypotenuse";
        EXPECT_FALSE(test(A, B, C, Ray{{0.2f, 0.2f, 1}, 0, {0, 0, 1}, kInfinity}, h)) << "behind the origin";
        EXPECT_FALSE(test(A, B, C, Ray{{0.2f, 0.2f, 1}, 0, {0, 0, -1}, 0.5f}, h)) << "beyond tmax";
        EXPECT_FALSE(test(A, B, C, Ray{{0.2f, 0.2f, 1}, 1.5f, {0, 0, -1}, kInfinity}, h)) << "before tmin";
        EXPECT_TRUE(test(A, B, C, Ray{{0.2f, 0.2f, 1}, 1.0f, {0, 0, -1}, 1.0f}, h)) << "t == tmin == tmax";
        EXPECT_FALSE(test(A, B, C, Ray{{-1, 0.2f, 0}, 0, {1, 0, 0}, kInfinity}, h)) << "ray in the plane";
        EXPECT_FALSE(test(A, A, B, Ray{{0.5f, 0, 1}, 0, {0, 0, -1}, kInfinity}, h)) << "degenerate triangle";
        EXPECT_FALSE(test(A, B, C, Ray{{0.2f, 0.2f, 1}, 0, {0, 0, 0}, kInfinity}, h)) << "zero direction";
    });
}

TEST(Triangle, RayStartingOnTheSurfaceHitsAtZero) {
    for_both_tests([](TriangleTest, auto test) {
        TriangleHit h{};
        ASSERT_TRUE(test(A, B, C, Ray{{0.2f, 0.2f, 0}, 0, {0.3f, 0.1f, 1}, kInfinity}, h));
        EXPECT_EQ(h.t, 0.0f);
    });
}

TEST(Triangle, WatertightTestNeverLeaksThroughSharedEdges) {
    // A fan of triangles around a shared vertex, shot exactly at points on the shared edges and at
    // the shared vertex from many directions: at least one triangle must report a hit every time.
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const int n = 7;
    std::vector<Vec3> rim;
    for (int i = 0; i < n; ++i) {
        const float a = 2.0f * 3.14159265f * float(i) / n;
        rim.push_back({std::cos(a) * 1.3f + 0.1f, std::sin(a) * 0.9f, 0.05f * float(i % 3)});
    }
    const Vec3 hub{0.07f, -0.03f, 0.2f};
    size_t watertight_leaks = 0, rays = 0;
    for (int k = 0; k < 20000; ++k) {
        const int e = k % n;
        const float s = std::fabs(u(rng));
        const Vec3 target = (k % 5 == 0) ? hub : hub + (rim[e] - hub) * s;
        const Vec3 o{u(rng) * 3, u(rng) * 3, 2.0f + std::fabs(u(rng))};
        const Ray r{o, 0, target - o, kInfinity};
        bool hit = false;
        for (int i = 0; i < n; ++i) {
            TriangleHit h{};
            hit = hit || intersect_watertight(hub, rim[i], rim[(i + 1) % n], r, r.tmax, h);
        }
        ++rays;
        watertight_leaks += hit ? 0 : 1;
    }
    EXPECT_EQ(watertight_leaks, 0u) << "of " << rays << " rays through shared edges and the shared vertex";
}

TEST(Triangle, BothTestsAgreeAwayFromEdges) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int k = 0; k < 20000; ++k) {
        const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
        const Vec3 o{u(rng) * 3, u(rng) * 3, u(rng) * 3};
        const Ray r{o, 0, Vec3{u(rng), u(rng), u(rng)}, kInfinity};
        TriangleHit hm{}, hw{};
        const bool m = intersect_moller(a, b, c, r, r.tmax, hm);
        const bool w = intersect_watertight(a, b, c, r, r.tmax, hw);
        if (m && w) {
            EXPECT_NEAR(hm.t, hw.t, 1e-3f * std::max(1.0f, hm.t));
            EXPECT_NEAR(hm.u, hw.u, 1e-3f);
            EXPECT_NEAR(hm.v, hw.v, 1e-3f);
        } else if (m != w) {
            // Disagreement is allowed only at an edge: some barycentric must be ~0.
            const TriangleHit& h = m ? hm : hw;
            const float w0 = 1.0f - h.u - h.v;
            EXPECT_LT(std::min({h.u, h.v, w0}), 1e-4f) << "case " << k;
        }
    }
}

}  // namespace
}  // namespace thicket::triangle_test
