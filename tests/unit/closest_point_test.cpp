// The closest point on a triangle: each Voronoi region by a known answer, then random points
// against dense sampling of the triangle, and the degenerate (collinear) fallback.
#include <gtest/gtest.h>

#include <random>

#include "thicket/accel/registry.h"
#include "thicket/core/closest_point.h"
#include "thicket/scene/scene.h"

namespace thicket::closest_point_test {
namespace {

const Vec3 A{0, 0, 0}, B{2, 0, 0}, C{0, 2, 0};

void expect_point(const TrianglePoint& q, Vec3 want, float u, float v) {
    EXPECT_NEAR(q.point.x, want.x, 1e-6f);
    EXPECT_NEAR(q.point.y, want.y, 1e-6f);
    EXPECT_NEAR(q.point.z, want.z, 1e-6f);
    EXPECT_NEAR(q.u, u, 1e-6f);
    EXPECT_NEAR(q.v, v, 1e-6f);
}

TEST(ClosestPoint, EveryRegion) {
    expect_point(closest_point_on_triangle({-1, -1, 3}, A, B, C), A, 0, 0);          // vertex a
    expect_point(closest_point_on_triangle({3, -1, 0}, A, B, C), B, 1, 0);           // vertex b
    expect_point(closest_point_on_triangle({-1, 3, 1}, A, B, C), C, 0, 1);           // vertex c
    expect_point(closest_point_on_triangle({1, -2, 0}, A, B, C), {1, 0, 0}, 0.5f, 0);   // edge ab
    expect_point(closest_point_on_triangle({-2, 1, 0}, A, B, C), {0, 1, 0}, 0, 0.5f);   // edge ac
    expect_point(closest_point_on_triangle({2, 2, -1}, A, B, C), {1, 1, 0}, 0.5f, 0.5f);  // edge bc
    expect_point(closest_point_on_triangle({0.5f, 0.5f, 4}, A, B, C), {0.5f, 0.5f, 0}, 0.25f, 0.25f);  // face
}

TEST(ClosestPoint, NoSampleOfTheTriangleIsCloser) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> d(-3.0f, 3.0f);
    const Vec3 a{0.3f, -1, 0.2f}, b{1.7f, 0.4f, -0.5f}, c{-0.6f, 1.1f, 0.9f};
    for (int i = 0; i < 300; ++i) {
        const Vec3 p{d(rng), d(rng), d(rng)};
        const TrianglePoint q = closest_point_on_triangle(p, a, b, c);
        const Vec3 from_uv = a + (b - a) * q.u + (c - a) * q.v;
        EXPECT_NEAR(length(from_uv - q.point), 0.0f, 1e-5f) << "the uv must name the point";
        const float got = length(p - q.point);
        float best = kInfinity;
        constexpr int kSteps = 100;
        for (int s = 0; s <= kSteps; ++s)
            for (int t = 0; s + t <= kSteps; ++t) {
                const Vec3 x = a + (b - a) * (float(s) / kSteps) + (c - a) * (float(t) / kSteps);
                best = std::min(best, length(p - x));
            }
        EXPECT_LE(got, best + 1e-5f) << "a sample of the triangle is closer";
        EXPECT_GE(got, best - 0.03f) << "farther than the sampling's resolution allows";
    }
}

TEST(ClosestPoint, CollinearTriangleAnswersOnItsSegments) {
    const Vec3 a{0, 0, 0}, b{1, 0, 0}, c{3, 0, 0};
    const TrianglePoint q = closest_point_on_triangle({2, 1, 0}, a, b, c);
    EXPECT_NEAR(q.point.x, 2.0f, 1e-6f);
    EXPECT_NEAR(q.point.y, 0.0f, 1e-6f);
}

TEST(ClosestPoint, BoxDistance) {
    const Aabb box{{0, 0, 0}, {1, 1, 1}};
    EXPECT_EQ(distance2_to_box({0.5f, 0.5f, 0.5f}, box), 0.0f);
    EXPECT_FLOAT_EQ(distance2_to_box({2, 0.5f, 3}, box), 1.0f + 4.0f);
}

// Issue 31: the region tests multiply four coordinate differences; in float a unit triangle seen
// from 1e20, or a 2e10 triangle from 4e10, overflowed to inf and NaN and picked a wrong region.
TEST(ClosestPoint, FarPointsAndLargeTrianglesStayExact) {
    const TrianglePoint far = closest_point_on_triangle({1e20f, 0, 0}, A, B, C);
    expect_point(far, B, 1, 0);
    EXPECT_FLOAT_EQ(point_distance({1e20f, 0, 0}, far.point), 1e20f);
    const float s = 1e10f;
    const TrianglePoint face = closest_point_on_triangle({0.5f * s, 0.5f * s, 4 * s}, A * s, B * s, C * s);
    EXPECT_NEAR(face.u, 0.25f, 1e-6f);
    EXPECT_NEAR(face.v, 0.25f, 1e-6f);
    EXPECT_FLOAT_EQ(face.point.z, 0.0f);
    EXPECT_FLOAT_EQ(point_distance({0.5f * s, 0.5f * s, 4 * s}, face.point), 4 * s);
    // A box's squared distance past float's range stays finite (and ordered) in double.
    const Aabb box{{0, 0, 0}, {1, 1, 1}};
    const double d = double(1e20f) - 1.0;
    EXPECT_DOUBLE_EQ(distance2_to_box({1e20f, 0.5f, 0.5f}, box), d * d);
    EXPECT_LT(distance2_to_box({1e20f, 0.5f, 0.5f}, box), distance2_to_box({2e20f, 0.5f, 0.5f}, box));
}

// The conformance rule for far points: every structure answers brute force's primitive, with a
// finite distance; before, bvh and bvh8 answered prim 0 at distance inf and brute force nothing.
TEST(ClosestPoint, FarPointsGetBruteForcesPrimitiveFromEveryStructure) {
    const Scene scene = load_scene("cornell");
    const std::unique_ptr<Accel> brute = build_accel("brute", scene);
    const Vec3 points[] = {{1e20f, 0, 0}, {0, 1e20f, 0}, {-3e19f, 2e19f, 1e20f}, {0.3f, -1e25f, 0.2f}, {3e38f, 3e38f, 3e38f}};
    for (const char* spec : {"bvh", "bvh8"}) {
        const std::unique_ptr<Accel> accel = build_accel(spec, scene);
        for (const Vec3& p : points) {
            const NearestPoint want = brute->closest_point(p), got = accel->closest_point(p);
            ASSERT_TRUE(want.found()) << p.x << "," << p.y << "," << p.z;
            EXPECT_EQ(got.prim, want.prim) << spec << " at " << p.x << "," << p.y << "," << p.z;
            EXPECT_EQ(got.distance, want.distance) << spec;
            if (max_component(abs(p)) < 1e30f) {
                EXPECT_TRUE(std::isfinite(got.distance)) << spec;
                EXPECT_NEAR(got.distance / length(p / 1e20f), 1e20f, 1e15f) << spec;
            }
        }
    }
}

}  // namespace
}  // namespace thicket::closest_point_test
