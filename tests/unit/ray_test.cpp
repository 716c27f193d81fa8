// make_ray: the one rule for which 8-float rays are traced (the CLI's trace and any binding).
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "thicket/core/ray.h"

namespace thicket::ray_test {
namespace {

TEST(MakeRay, AcceptsAMeaningfulRayAsGiven) {
    const std::array<float, 8> r = {1, 2, 3, 0, 0, -1, 0.5f, kInfinity};
    Ray ray;
    ASSERT_TRUE(make_ray(r.data(), ray));
    EXPECT_EQ(ray.org, Vec3(1, 2, 3));
    EXPECT_EQ(ray.dir, Vec3(0, 0, -1));
    EXPECT_EQ(ray.tmin, 0.5f);
    EXPECT_EQ(ray.tmax, kInfinity);
    const std::array<float, 8> point_interval = {0, 0, 0, 1, 0, 0, 2, 2};  // tmin == tmax is allowed
    EXPECT_TRUE(make_ray(point_interval.data(), ray));
}

TEST(MakeRay, RefusesRaysWithoutMeaningAndLeavesTheRayAlone) {
    const float nan = std::nanf("");
    const std::array<float, 8> bad[] = {
        {nan, 0, 0, 1, 0, 0, 0, 1},        {kInfinity, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0, nan, 0, 0, 0, 1},
        {0, 0, 0, kInfinity, 0, 0, 0, 1}, {0, 0, 0, 0, 0, 0, 0, 1},         {0, 0, 0, 1, 0, 0, nan, 1},
        {0, 0, 0, 1, 0, 0, 0, nan},       {0, 0, 0, 1, 0, 0, 2, 1},
    };
    for (const auto& r : bad) {
        Ray ray;
        ray.tmin = 7.0f;
        EXPECT_FALSE(make_ray(r.data(), ray)) << r[0] << " " << r[3] << " " << r[6] << " " << r[7];
        EXPECT_EQ(ray.tmin, 7.0f) << "untouched";
    }
}

}  // namespace
}  // namespace thicket::ray_test
