// The sphere kernel against the textbook quadratic solved in quad precision (113-bit), where
// cancellation cannot hurt: near, far, tiny and huge spheres, rays from inside, windows.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>

#include "support/test_scenes.h"
#include "thicket/prims/sphere.h"

namespace thicket::sphere_test {
namespace {

using Quad = __float128;

Quad quad_sqrt(Quad v) {
    Quad x = std::sqrt(static_cast<long double>(v));
    for (int i = 0; i < 3; ++i) x = 0.5 * (x + v / x);  // Newton from the long double guess
    return x;
}

/// Both roots of |o + t d - c|^2 = r^2 by the naive formula, in quad precision; nullopt on a miss.
std::optional<std::pair<double, double>> quad_roots(const Sphere& s, const Ray& ray) {
    const Quad fx = Quad(ray.org.x) - s.center.x, fy = Quad(ray.org.y) - s.center.y, fz = Quad(ray.org.z) - s.center.z;
    const Quad dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
    const Quad a = dx * dx + dy * dy + dz * dz;
    const Quad b = fx * dx + fy * dy + fz * dz;
    const Quad c = fx * fx + fy * fy + fz * fz - Quad(s.radius) * s.radius;
    const Quad disc = b * b - a * c;
    if (disc < 0) return std::nullopt;
    const Quad sq = quad_sqrt(disc);
    return std::make_pair(double((-b - sq) / a), double((-b + sq) / a));
}

/// The first root the kernel should report for the window [tmin, tmax].
std::optional<double> expected_t(const Sphere& s, const Ray& ray) {
    const auto roots = quad_roots(s, ray);
    if (!roots) return std::nullopt;
    for (double t : {roots->first, roots->second})
        if (t >= ray.tmin && t <= ray.tmax) return t;
    return std::nullopt;
}

using testing::random_unit_vector;

struct Case {
    const char* what;
    Vec3 center;
    float radius;
    float distance;  ///< of the ray origins from the centre, in radii
};

/// Rays aimed at random points of a disc of 1.2 radii around the centre, from `distance`; t errors
/// stay within float rounding of the exact root (the kernel works in double).
void check_case(const Case& c, uint32_t seed) {
    SCOPED_TRACE(c.what);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.2f, 1.2f);
    const Sphere s{c.center, c.radius};
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
        const Vec3 o = c.center + random_unit_vector(rng) * (c.radius * c.distance);
        const Vec3 target = c.center + Vec3{u(rng), u(rng), u(rng)} * c.radius;
        Ray ray{o, 0.0f, target - o, kInfinity};
        if (i % 3 == 1) ray.dir = normalize(ray.dir);
        if (i % 3 == 2) ray.dir = ray.dir * 1e3f;  // t in units of a long direction
        const auto want = expected_t(s, ray);
        const auto roots = quad_roots(s, ray);
        ShapeHit h;
        const bool got = s.intersect(ray, ray.tmax, h);
        // Skip the rays within rounding of tangency: either answer is right there.
        if (roots) {
            const double half_chord = std::fabs(roots->second - roots->first) * length(ray.dir) / 2;
            if (half_chord < 1e-3 * c.radius) continue;
        }
        ASSERT_EQ(got, want.has_value()) << "ray " << i;
        if (!got) continue;
        ++hits;
        const double scale = double(c.radius) + std::fabs(*want) * length(ray.dir);
        EXPECT_LE(std::fabs(double(h.t) - *want) * length(ray.dir), 1e-6 * scale) << "ray " << i;
        EXPECT_GE(h.u, 0.0f);
        EXPECT_LT(h.u, 1.0f);
        EXPECT_GE(h.v, 0.0f);
        EXPECT_LE(h.v, 1.0f);
        // The normal from (u, v) is (p - c) / r at the exact hit point.
        const Vec3d p = Vec3d(ray.org) + Vec3d(ray.dir) * *want;
        const Vec3d n_exact = (p - Vec3d(c.center)) / double(c.radius);
        const Vec3 n = s.normal(ray.org + ray.dir * h.t, h.u, h.v);
        EXPECT_NEAR(length(n), 1.0f, 1e-6f);
        EXPECT_NEAR(dot(Vec3d(n), n_exact), 1.0, 1e-6) << "ray " << i;
    }
    EXPECT_GT(hits, 1000);
}

TEST(Sphere, MatchesTheQuadPrecisionQuadratic) {
    check_case({"unit sphere, near", {0.3f, -0.2f, 0.1f}, 1.0f, 3.0f}, 1);
    check_case({"unit sphere at distance 1e4", {0, 0, 0}, 1.0f, 1e4f}, 2);
    check_case({"unit sphere at distance 1e6", {5, 5, 5}, 1.0f, 1e6f}, 3);
    check_case({"tiny sphere (1e-6)", {1, 2, 3}, 1e-6f, 5.0f}, 4);
    check_case({"tiny sphere seen from 1e7 radii", {0.5f, 0, 0}, 1e-6f, 1e7f}, 5);
    check_case({"huge sphere (1e6)", {0, -1e6f, 0}, 1e6f, 2.0f}, 6);
    check_case({"sphere far from the origin", {1e5f, -3e4f, 2e5f}, 10.0f, 4.0f}, 7);
}

TEST(Sphere, FromInsideTheFarRootIsReported) {
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> u(-0.9f, 0.9f);
    for (const float r : {1e-5f, 1.0f, 1e5f}) {
        const Sphere s{{1, 2, 3}, r};
        for (int i = 0; i < 2000; ++i) {
            Vec3 o{u(rng), u(rng), u(rng)};
            if (dot(o, o) >= 0.81f) continue;
            const Ray ray{s.center + o * r, 0.0f, random_unit_vector(rng), kInfinity};
            const auto roots = quad_roots(s, ray);
            ASSERT_TRUE(roots);
            ASSERT_LT(roots->first, 0.0);
            ShapeHit h;
            ASSERT_TRUE(s.intersect(ray, kInfinity, h)) << i;
            EXPECT_NEAR(h.t, roots->second, 1e-6 * r) << i;
            EXPECT_GT(h.t, 0.0f);
            // The normal still points outward, along the ray's exit.
            EXPECT_GT(dot(s.normal(ray.org + ray.dir * h.t, h.u, h.v), ray.dir), 0.0f);
        }
    }
}

TEST(Sphere, WindowPicksTheRootAndNeverChangesIt) {
    const Sphere s{{0, 0, 0}, 1.0f};
    const Ray ray{{0, 0, -5}, 0.0f, {0, 0, 1}, kInfinity};  // roots at t = 4 and 6
    ShapeHit h;
    ASSERT_TRUE(s.intersect(ray, kInfinity, h));
    EXPECT_EQ(h.t, 4.0f);
    EXPECT_FLOAT_EQ(h.v, 0.5f);  // on the equator
    const float first = h.t;
    ASSERT_TRUE(s.intersect(ray, first, h)) << "tmax is inclusive";
    EXPECT_EQ(h.t, first) << "the root does not depend on the window";
    EXPECT_FALSE(s.intersect(ray, 3.999f, h));
    Ray later = ray;
    later.tmin = 4.5f;
    ASSERT_TRUE(s.intersect(later, kInfinity, h));
    EXPECT_EQ(h.t, 6.0f);
    later.tmin = 6.5f;
    EXPECT_FALSE(s.intersect(later, kInfinity, h));
    // Zero and non-finite directions are misses, not NaN hits.
    EXPECT_FALSE(s.intersect({{0, 0, -5}, 0.0f, {0, 0, 0}, kInfinity}, kInfinity, h));
    EXPECT_FALSE(s.intersect({{0, 0, -5}, 0.0f, {0, NAN, 1}, kInfinity}, kInfinity, h));
}

TEST(Sphere, UvConventionAndNormals) {
    const Sphere s{{1, 1, 1}, 2.0f};
    ShapeHit h;
    // From +y straight down: the +y pole, v = 0.
    ASSERT_TRUE(s.intersect({{1, 5, 1}, 0.0f, {0, -1, 0}, kInfinity}, kInfinity, h));
    EXPECT_EQ(h.v, 0.0f);
    // From +x: phi = 0; from -z: phi = pi/2 (right-handed about +y from +x towards -z).
    ASSERT_TRUE(s.intersect({{5, 1, 1}, 0.0f, {-1, 0, 0}, kInfinity}, kInfinity, h));
    EXPECT_NEAR(h.u, 0.0f, 1e-7f);
    EXPECT_NEAR(h.v, 0.5f, 1e-7f);
    ASSERT_TRUE(s.intersect({{1, 1, -5}, 0.0f, {0, 0, 1}, kInfinity}, kInfinity, h));
    EXPECT_NEAR(h.u, 0.25f, 1e-7f);
    const Vec3 n = s.normal({}, h.u, h.v);
    EXPECT_NEAR(n.z, -1.0f, 1e-6f);
}

TEST(Sphere, BoundsEncloseTheSphereInFloat) {
    // c + r rounds back to c in float: the box must still be strictly wider.
    const Sphere s{{1e7f, -1e7f, 0}, 0.3f};
    const Aabb b = s.bounds();
    EXPECT_GT(b.max.x, 1e7f);
    EXPECT_LT(b.min.x, 1e7f);
    EXPECT_LT(b.min.y, -1e7f);
    EXPECT_GE(double(b.max.z), 0.3);
    EXPECT_LE(double(b.min.z), -0.3);
}

}  // namespace
}  // namespace thicket::sphere_test
