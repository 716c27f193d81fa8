// bvh8's kernels against the scalar reference tests they must reproduce bitwise, under every ISA
// this CPU runs: the 8-wide slab test against traversal_box_entry below, the 4-lane Moller-Trumbore against
// intersect_moller. The conformance suite checks whole queries; these pin each kernel alone, on
// the cases that break SIMD code (axis-parallel rays with +-0, origins on slab planes, NaN).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "thicket/bvh8/isa.h"
#include "thicket/core/ray_box.h"
#include "thicket/core/triangle.h"

namespace thicket::bvh8_kernels_test {
namespace {

using thicket::Isa;

uint32_t bits(float x) {
    uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
}

/// The traversal's box test as written in docs/bvh8.md, one scalar line per step: Ize's slab test
/// (far planes widened by 2 gamma(3), NaN candidates dropped) over the ray's interval [tmin, tmax]
/// widened by kSlabSlack relative at both ends, the far end capped at the largest float (so that
/// a box entered at +inf is a miss). Not ray_box_entry: that one widens every plane by the slack,
/// which makes a far ray a cylinder of radius ~1e-4 t.
float traversal_box_entry(const Ray& ray, const Vec3& lo, const Vec3& hi) {
    const float s = kSlabSlack, g = 2.0f * rounding_gamma(3);
    float t0 = std::min(ray.tmin * (1.0f - s), ray.tmin * (1.0f + s));
    float t1 = std::max(ray.tmax * (1.0f + s), ray.tmax * (1.0f - s));
    t1 = t1 < 3.402823466e+38f ? t1 : 3.402823466e+38f;
    for (int a = 0; a < 3; ++a) {
        const float inv = 1.0f / ray.dir[a];
        const bool neg = std::signbit(inv);
        const float near_t = ((neg ? hi : lo)[a] - ray.org[a]) * inv;
        float far_t = ((neg ? lo : hi)[a] - ray.org[a]) * inv;
        far_t *= far_t > 0.0f ? 1.0f + g : 1.0f - g;
        t0 = near_t > t0 ? near_t : t0;
        t1 = far_t < t1 ? far_t : t1;
    }
    return t0 <= t1 ? t0 : kInfinity;
}

/// A node of 8 random boxes on a coarse grid (so that origins often lie exactly on a plane),
/// lane 7 left empty.
bvh8::Node random_node(std::mt19937& rng) {
    std::uniform_int_distribution<int> cell(-4, 4);
    bvh8::Node node{};
    node.valid = 0x7f;
    for (int lane = 0; lane < 8; ++lane)
        for (int a = 0; a < 3; ++a) {
            const float lo = float(cell(rng)), hi = lo + float(cell(rng) + 4) * 0.5f;
            node.box[a][0][lane] = lane == 7 ? kInfinity : lo;
            node.box[a][1][lane] = lane == 7 ? -kInfinity : hi;
        }
    return node;
}

/// Rays from grid points, half of them with axis-parallel (+0 or -0) components.
Ray random_ray(std::mt19937& rng) {
    std::uniform_int_distribution<int> cell(-5, 5), pick(0, 5);
    Ray r;
    r.org = Vec3(float(cell(rng)), float(cell(rng)), float(cell(rng))) * 0.5f;
    for (int a = 0; a < 3; ++a) {
        const int p = pick(rng);
        r.dir[a] = p == 0 ? 0.0f : (p == 1 ? -0.0f : float(cell(rng)) * 0.37f + 0.01f);
    }
    if (r.dir == Vec3(0.0f)) r.dir.x = 1.0f;
    r.tmin = pick(rng) == 0 ? 0.5f : 0.0f;
    r.tmax = pick(rng) == 0 ? 3.0f : kInfinity;
    return r;
}

TEST(Bvh8Kernels, EveryIsaRunsItsOwnTable) {
    for (Isa isa : cpu_isas()) EXPECT_STREQ(bvh8::kernels_for(isa).isa, isa_name(isa));
}

TEST(Bvh8Kernels, NodeTestIsRayBoxEntryBitwiseOnEveryLane) {
    std::mt19937 rng(7);
    size_t entered = 0, checked = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const bvh8::Node node = random_node(rng);
        const Ray ray = random_ray(rng);
        for (Isa isa : cpu_isas()) {
            float dist[8];
            uint32_t any = 0;
            const uint32_t mask = bvh8::kernels_for(isa).node_test(&node, 1, ray, ray.tmax, dist, &any);
            ASSERT_EQ(any, mask);
            for (int lane = 0; lane < 8; ++lane) {
                const bool valid = (node.valid >> lane) & 1;
                const float want =
                    valid ? traversal_box_entry(ray, Vec3(node.box[0][0][lane], node.box[1][0][lane], node.box[2][0][lane]),
                                                Vec3(node.box[0][1][lane], node.box[1][1][lane], node.box[2][1][lane]))
                          : kInfinity;
                const bool hit = (mask >> lane) & 1;
                ASSERT_EQ(hit, want != kInfinity) << isa_name(isa) << " trial " << trial << " lane " << lane;
                if (hit) {
                    ASSERT_EQ(bits(dist[lane]), bits(want)) << isa_name(isa) << " trial " << trial;
                }
                entered += hit;
                ++checked;
            }
        }
    }
    // Both outcomes occur often enough for the comparison to mean something.
    EXPECT_GT(entered, checked / 50);
    EXPECT_LT(entered, checked / 2);
}

TEST(Bvh8Kernels, NodeTestNeverEntersAnEmptyLaneEvenForNanRays) {
    std::mt19937 rng(3);
    const bvh8::Node node = random_node(rng);
    const float nan = std::nanf("");
    for (const Ray& ray : {Ray{{nan, 0, 0}, 0.0f, {1, 0, 0}, kInfinity}, Ray{{0, 0, 0}, 0.0f, {nan, nan, nan}, kInfinity},
                           Ray{{0, 0, 0}, 0.0f, {kInfinity, 1, 0}, kInfinity}})
        for (Isa isa : cpu_isas()) {
            float dist[8];
            uint32_t any = 0;
            EXPECT_EQ(bvh8::kernels_for(isa).node_test(&node, 1, ray, ray.tmax, dist, &any) >> 7, 0u)
                << isa_name(isa);
        }
}

TEST(Bvh8Kernels, BlockTestIsMollerTrumboreBitwise) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coord(-1.0f, 1.0f);
    size_t hits = 0;
    for (int trial = 0; trial < 5000; ++trial) {
        bvh8::Tri4 block{};
        Vec3 v[4][3];
        for (int lane = 0; lane < 4; ++lane)
            for (int k = 0; k < 3; ++k) {
                v[lane][k] = Vec3(coord(rng), coord(rng), coord(rng) * 0.1f);
                for (int a = 0; a < 3; ++a) block.v[k][a][lane] = v[lane][k][a];
            }
        Ray ray{{coord(rng) * 0.5f, coord(rng) * 0.5f, 3.0f}, 0.0f, {coord(rng) * 0.1f, coord(rng) * 0.1f, -1.0f}, 3.5f};
        for (Isa isa : cpu_isas()) {
            float t[4];
            const uint32_t mask = bvh8::kernels_for(isa).block_test(block, ray, ray.tmax, t);
            for (int lane = 0; lane < 4; ++lane) {
                TriangleHit want;
                const bool hit = intersect_moller(v[lane][0], v[lane][1], v[lane][2], ray, ray.tmax, want);
                ASSERT_EQ(bool((mask >> lane) & 1), hit) << isa_name(isa) << " trial " << trial;
                if (hit) {
                    ASSERT_EQ(bits(t[lane]), bits(want.t)) << isa_name(isa) << " trial " << trial;
                }
                hits += hit;
            }
        }
    }
    EXPECT_GT(hits, 1000u);
}

TEST(Bvh8Kernels, AZeroLaneIsNeverHit) {
    bvh8::Tri4 block{};  // all-zero vertices: the padding of a partly filled block
    const Ray ray{{0, 0, 1}, 0.0f, {0, 0, -1}, kInfinity};
    for (Isa isa : cpu_isas()) {
        float t[4];
        EXPECT_EQ(bvh8::kernels_for(isa).block_test(block, ray, ray.tmax, t), 0u) << isa_name(isa);
    }
}

}  // namespace
}  // namespace thicket::bvh8_kernels_test
