// Reordered batches (accel/ray_order.h): the sort is a permutation in key order, a reordered
// batch answers every ray in its own place, costly blocks are really traced sorted and cheap
// ones as given, and real structures give bit-identical answers either way.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <random>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/accel/ray_order.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/query/ray_rows.h"
#include "support/test_scenes.h"

namespace thicket::ray_order_test {

std::vector<Ray> random_rays(size_t n, uint32_t seed, float spread = 1.0f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<Ray> rays(n);
    for (Ray& r : rays) {
        r.org = {spread * u(rng), spread * u(rng), spread * u(rng)};
        do r.dir = {u(rng), u(rng), u(rng)};
        while (r.dir.x == 0 && r.dir.y == 0 && r.dir.z == 0);
    }
    return rays;
}

/// The key RayOrder::sort gives ray r in a block whose finite origins span [lo, hi].
uint32_t key_of(const Ray& r, const Vec3& lo, const Vec3& hi) {
    const uint32_t octant = uint32_t(r.dir.x < 0) | uint32_t(r.dir.y < 0) << 1 | uint32_t(r.dir.z < 0) << 2;
    uint32_t morton = 0;
    for (int a = 0; a < 3; ++a) {
        const float extent = hi[a] - lo[a];
        const float scale = extent > 0 ? float(1 << RayOrder::kOriginBits) / extent : 0.0f;
        const uint32_t q = quantise_origin((r.org[a] - lo[a]) * scale);
        for (int b = 0; b < RayOrder::kOriginBits; ++b) morton |= ((q >> b) & 1u) << (3 * b + a);
    }
    return octant << (3 * RayOrder::kOriginBits) | morton;
}

TEST(RayOrder, SortsAPermutationByOctantThenMortonCodeAndKeepsTiesInInputOrder) {
    for (size_t n : {size_t(1), size_t(7), size_t(5000), size_t(65536)}) {
        const std::vector<Ray> rays = random_rays(n, uint32_t(n));
        RayOrder order;
        order.sort(n, [&](size_t i, Vec3& org, Vec3& dir) { org = rays[i].org, dir = rays[i].dir; });
        ASSERT_EQ(order.order.size(), n);
        Vec3 lo = rays[0].org, hi = rays[0].org;
        for (const Ray& r : rays) lo = min(lo, r.org), hi = max(hi, r.org);
        std::vector<uint8_t> seen(n, 0);
        for (size_t k = 0; k < n; ++k) {
            ASSERT_LT(order.order[k], n);
            ASSERT_EQ(seen[order.order[k]]++, 0) << "index " << order.order[k] << " twice";
            if (k == 0) continue;
            const uint32_t a = key_of(rays[order.order[k - 1]], lo, hi), b = key_of(rays[order.order[k]], lo, hi);
            ASSERT_LE(a, b) << "position " << k << " of " << n;
            if (a == b) {
                ASSERT_LT(order.order[k - 1], order.order[k]) << "a tie out of input order at " << k;
            }
        }
    }
}

TEST(RayOrder, NonFiniteAndHugeOriginsGetAKeyWithoutDisturbingTheOthers) {
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<Ray> rays = random_rays(1000, 5);
    rays[3].org = {nan, 0, 0};
    rays[10].org = {inf, -inf, 0};
    rays[20].dir = {nan, nan, nan};
    std::vector<Ray> huge = rays;
    huge[30].org = {3e38f, -3e38f, 1e-38f};  // the bounds' extent overflows a float
    for (const std::vector<Ray>* set : {&rays, &huge}) {
        RayOrder order;
        order.sort(set->size(), [&](size_t i, Vec3& org, Vec3& dir) { org = (*set)[i].org, dir = (*set)[i].dir; });
        std::vector<uint8_t> seen(set->size(), 0);
        for (uint32_t i : order.order) ASSERT_EQ(seen.at(i)++, 0);
    }
}

TEST(RayOrder, BlocksLeaveEveryWorkerTwoAndStayWithinTheLimits) {
    EXPECT_EQ(reorder_block(1000000, 1), kReorderBlock);
    EXPECT_EQ(reorder_block(1000000, 8), 62500u / 256 * 256);  // two blocks a worker, a multiple of 256
    EXPECT_EQ(reorder_block(kReorderMin, 2), kReorderMin);
    for (unsigned w : {1u, 2u, 3u, 64u})
        for (size_t n : {size_t(4096), size_t(100000), size_t(10000000)}) {
            const size_t b = reorder_block(n, w);
            EXPECT_EQ(b % 256, 0u);
            EXPECT_GE(b, kReorderMin);
            EXPECT_LE(b, kReorderBlock);
        }
}

/// A structure whose answer names the ray it was asked about (t = tmax, the ray's number) and
/// which records the order rays reach it; each ray costs `cost`.
class OrderWitness : public Accel {
public:
    explicit OrderWitness(std::chrono::nanoseconds cost) : cost_(cost) {}
    using Accel::intersect;
    using Accel::occluded;
    Aabb bounds() const override { return Aabb{}; }
    Hit intersect(const Ray& ray) const override {
        const auto until = std::chrono::steady_clock::now() + cost_;
        while (std::chrono::steady_clock::now() < until) {
        }
        std::lock_guard<std::mutex> lock(mutex_);
        seen_.push_back(uint32_t(ray.tmax));
        return Hit{ray.tmax, 0.0f, 0.0f, uint32_t(ray.tmax)};
    }
    Hit intersect(const Ray& ray, RayCounters&) const override { return intersect(ray); }
    bool occluded(const Ray& ray) const override { return uint32_t(intersect(ray).prim) % 3 == 0; }
    bool occluded(const Ray& ray, RayCounters&) const override { return occluded(ray); }
    AccelStats stats() const override { return base_stats(); }
    std::vector<uint32_t> seen() const { return seen_; }

private:
    std::chrono::nanoseconds cost_;
    mutable std::mutex mutex_;
    mutable std::vector<uint32_t> seen_;
};

std::vector<Ray> numbered_rays(size_t n) {
    std::vector<Ray> rays = random_rays(n, 11, 5.0f);
    for (size_t i = 0; i < n; ++i) rays[i].tmax = float(i);  // exact up to 2^24
    return rays;
}

TEST(ReorderedBatches, CostlyRaysAreTracedSortedAndAnsweredInTheirOwnPlace) {
    const size_t n = 3 * kReorderMin + 100;
    const std::vector<Ray> rays = numbered_rays(n);
    for (const bool reorder : {false, true}) {
        const OrderWitness accel(std::chrono::nanoseconds(400));
        BatchOptions options;
        options.threads = 1;
        options.reorder = reorder;
        size_t progressed = 0;
        options.progress = [&](size_t done) { progressed += done; };
        std::vector<Hit> hits(n);
        accel.intersect(rays, hits, options);
        EXPECT_EQ(progressed, n);
        for (size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].prim, i) << "reorder " << reorder;
        const std::vector<uint32_t> seen = accel.seen();
        ASSERT_EQ(seen.size(), n);
        size_t out_of_order = 0;
        for (size_t k = 1; k < n; ++k) out_of_order += seen[k] < seen[k - 1];
        if (!reorder) {
            EXPECT_EQ(out_of_order, 0u);
            continue;
        }
        // Each block's first two chunks as given, the rest in key order: thousands of steps back.
        const size_t block = reorder_block(n, 1);
        EXPECT_GT(out_of_order, n / 4);
        for (size_t begin = 0; begin < n; begin += block)
            for (size_t k = begin; k < std::min(n, begin + 2 * kBatchGrain); ++k) ASSERT_EQ(seen[k], k);
    }
}

TEST(ReorderedBatches, RaysCheaperThanTheThresholdAreTracedAsGiven) {
    const size_t n = 3 * kReorderMin;
    const std::vector<Ray> rays = numbered_rays(n);
    const OrderWitness accel(std::chrono::nanoseconds(0));
    BatchOptions options;
    options.threads = 1;
    options.reorder = true;
    options.reorder_from_ns = 1e6;  // a millisecond a ray: no build of this witness costs that much
    std::vector<uint8_t> occluded(n);
    accel.occluded(rays, occluded, options);
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(occluded[i], i % 3 == 0 ? 1 : 0) << i;
    const std::vector<uint32_t> seen = accel.seen();
    for (size_t k = 0; k < n; ++k) ASSERT_EQ(seen[k], k);
}

TEST(ReorderedBatches, RowsOfCostlyRaysAreSortedAndEachAnswerLandsOnItsRow) {
    const size_t n = 2 * kReorderMin + 77;
    std::vector<Ray> rays = numbered_rays(n);
    std::vector<float> data;
    for (size_t i = 0; i < n; ++i) {
        const Ray& r = rays[i];
        const float row[8] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, 0.0f, float(i)};
        data.insert(data.end(), row, row + 8);
    }
    data[8 * 5 + 3] = data[8 * 5 + 4] = data[8 * 5 + 5] = 0.0f;  // row 5: a zero direction, no ray
    const OrderWitness accel(std::chrono::nanoseconds(0));
    std::vector<Hit> hits(n);
    BatchOptions options;
    options.threads = 2;
    options.reorder = true;
    options.reorder_from_ns = 0.0;  // every block sorted
    const size_t without = closest_hits(accel, RayRows{data.data(), n, 8}, hits, options);
    EXPECT_EQ(without, 1u);
    for (size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].prim, i == 5 ? kNoPrim : i) << i;
    const std::vector<uint32_t> seen = accel.seen();
    size_t out_of_order = 0;
    for (size_t k = 1; k < seen.size(); ++k) out_of_order += seen[k] < seen[k - 1];
    EXPECT_GT(out_of_order, n / 4);
}

TEST(ReorderedBatches, RealStructuresAnswerBitForBitAsGiven) {
    const Scene scene = testing::nasty_scenes().back();  // the random soup
    const std::vector<Ray> rays = testing::conformance_rays(scene, 3 * kReorderMin, 3);
    for (const char* spec : {"bvh8", "bvh", "kdtree", "brute"}) {
        const auto accel = build_accel(spec, scene);
        std::vector<Hit> given(rays.size()), sorted(rays.size());
        std::vector<uint8_t> given_any(rays.size()), sorted_any(rays.size());
        BatchOptions options;
        options.reorder = false;
        accel->intersect(rays, given, options);
        accel->occluded(rays, given_any, options);
        options.reorder = true;
        options.reorder_from_ns = 0.0;  // every block sorted, however cheap the structure's rays
        accel->intersect(rays, sorted, options);
        accel->occluded(rays, sorted_any, options);
        size_t found = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            ASSERT_EQ(std::memcmp(&given[i], &sorted[i], sizeof(Hit)), 0) << spec << " ray " << i;
            ASSERT_EQ(given_any[i], sorted_any[i]) << spec << " ray " << i;
            found += given[i].found();
        }
        EXPECT_GT(found, rays.size() / 10) << spec;  // the comparison is not among misses only
    }
}

}  // namespace thicket::ray_order_test
