#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "thicket/core/ray_box.h"

namespace thicket::ray_box_test {
namespace {

const Aabb kUnit{{0, 0, 0}, {1, 1, 1}};

// Entry distances are widened outward by the documented slack (kSlabSlack, relative).
#define EXPECT_SLAB_T(got, want) EXPECT_NEAR((got), (want), 2.0f * kSlabSlack * std::fabs(want) + 1e-30f)

float entry(Vec3 o, Vec3 d, const Aabb& box = kUnit, float tmin = 0.0f, float tmax = kInfinity) {
    const Ray r{o, tmin, d, tmax};
    return ray_box_entry(RayBoxQuery(r), box, tmin, tmax);
}

TEST(RayBox, HitsAndMissesAlongAxes) {
    EXPECT_SLAB_T(entry({-1, 0.5f, 0.5f}, {1, 0, 0}), 1.0f);
    EXPECT_SLAB_T(entry({2, 0.5f, 0.5f}, {-1, 0, 0}), 1.0f);
    EXPECT_EQ(entry({-1, 1.5f, 0.5f}, {1, 0, 0}), kInfinity);
    EXPECT_EQ(entry({2, 0.5f, 0.5f}, {1, 0, 0}), kInfinity) << "box behind the ray";
}

TEST(RayBox, SignedZeroDirectionsNeverProduceNaNVerdicts) {
    // The origin lies exactly on the box's faces with a zero direction component of either sign:
    // the ray runs inside the face's plane, so the box must be reported as hit.
    for (float zero : {0.0f, -0.0f}) {
        for (float y : {0.0f, 1.0f, 0.5f}) {
            SCOPED_TRACE("zero sign " + std::to_string(std::signbit(zero)) + " y " + std::to_string(y));
            EXPECT_SLAB_T(entry({-1, y, 0.5f}, {1, zero, zero}), 1.0f);
            EXPECT_SLAB_T(entry({2, y, 0.5f}, {-1, zero, zero}), 1.0f);
            EXPECT_SLAB_T(entry({0.5f, y, 0.5f}, {zero, zero, 1}), 0.0f) << "origin inside or on the box";
        }
        EXPECT_EQ(entry({-1, 1.0001f, 0.5f}, {1, zero, zero}), kInfinity) << "just outside the face's plane";
        EXPECT_EQ(entry({-1, -0.0001f, 0.5f}, {1, zero, zero}), kInfinity);
    }
}

TEST(RayBox, FlatBoxesAreHit) {
    const Aabb flat{{0, 0, 0.5f}, {1, 1, 0.5f}};
    EXPECT_SLAB_T(entry({0.5f, 0.5f, -1}, {0, 0, 1}, flat), 1.5f);
    EXPECT_SLAB_T(entry({0.5f, 0.5f, 2}, {-0.0f, 0.0f, -1}, flat), 1.5f);
    // Ray lying in the flat box's plane, origin outside in x.
    EXPECT_SLAB_T(entry({-1, 0.5f, 0.5f}, {1, 0, 0}, flat), 1.0f);
    EXPECT_SLAB_T(entry({-1, 0.5f, 0.5f}, {1, 0, -0.0f}, flat), 1.0f);
    const Aabb point{{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}};
    EXPECT_SLAB_T(entry({0.5f, 0.5f, -1}, {0, 0, 1}, point), 1.5f);
}

TEST(RayBox, IntervalIsRespected) {
    EXPECT_EQ(entry({-1, 0.5f, 0.5f}, {1, 0, 0}, kUnit, 0.0f, 0.5f), kInfinity);
    EXPECT_SLAB_T(entry({-1, 0.5f, 0.5f}, {1, 0, 0}, kUnit, 0.0f, 1.0f), 1.0f) << "touching at tmax";
    EXPECT_SLAB_T(entry({-1, 0.5f, 0.5f}, {1, 0, 0}, kUnit, 1.5f, 10.0f), 1.5f) << "entry clamps to tmin";
    EXPECT_EQ(entry({-1, 0.5f, 0.5f}, {1, 0, 0}, kUnit, 2.5f, 10.0f), kInfinity) << "box lies before tmin";
}

TEST(RayBox, ConservativeForRaysThroughBoxCorners) {
    // Rays aimed exactly at corners and edges of boxes far from the origin, in every octant and at
    // huge and tiny scales: rounding must never cull a box the exact ray touches.
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float scale : {1e-7f, 1.0f, 1e7f}) {
        for (int i = 0; i < 20000; ++i) {
            const Vec3 lo = Vec3(u(rng), u(rng), u(rng)) * scale;
            const Vec3 hi = lo + Vec3(std::fabs(u(rng)), std::fabs(u(rng)), std::fabs(u(rng))) * scale;
            const Aabb box{lo, hi};
            const Vec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
            const Vec3 o = Vec3(u(rng), u(rng), u(rng)) * (4 * scale);
            if (box.contains(o)) continue;
            ASSERT_NE(entry(o, corner - o, box), kInfinity) << "scale " << scale << " case " << i;
        }
    }
}

}  // namespace
}  // namespace thicket::ray_box_test
