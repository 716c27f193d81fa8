// The traversal's slab test at one FMA per plane (docs/bvh8.md, "The slab test at one FMA per
// plane") against the exact one it stands in for, under every ISA this CPU runs: rays aimed at
// boxes' faces, edges and corners (and one float step inside or outside them), from near and far
// origins, must be entered by the FMA test wherever the exact test enters, at an entry distance no
// greater. That is all the traversal needs to return exactly the hits of the exact test: more boxes
// visited costs time, never an answer.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "thicket/bvh8/compress.h"
#include "thicket/bvh8/isa.h"
#include "thicket/core/ray_box.h"

namespace thicket::bvh8_fma_slab_test {
namespace {

using thicket::Isa;

/// A node of 8 boxes of sizes from `size` / 1000 to `size`, around `centre`.
bvh8::Node node_near(std::mt19937& rng, const Vec3& centre, float size) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), scale(-3.0f, 0.0f);
    bvh8::Node node{};
    node.valid = 0xff;
    for (int lane = 0; lane < 8; ++lane)
        for (int a = 0; a < 3; ++a) {
            const float extent = size * std::pow(10.0f, scale(rng));
            const float lo = centre[a] + unit(rng) * size;
            node.box[a][0][lane] = lo;
            node.box[a][1][lane] = lo + extent;
        }
    return node;
}

/// A point on lane's box: on a face, an edge or a corner (each coordinate either a plane or
/// strictly between), then nudged by at most one float step in or out on each axis.
Vec3 boundary_point(std::mt19937& rng, const bvh8::Node& node, int lane) {
    std::uniform_int_distribution<int> where(0, 2), nudge(-1, 1);
    std::uniform_real_distribution<float> inside(0.1f, 0.9f);
    Vec3 p;
    for (int a = 0; a < 3; ++a) {
        const float lo = node.box[a][0][lane], hi = node.box[a][1][lane];
        const int w = where(rng);
        float x = w == 0 ? lo : (w == 1 ? hi : lo + (hi - lo) * inside(rng));
        const int n = nudge(rng);
        if (n != 0) x = std::nextafter(x, n > 0 ? kInfinity : -kInfinity);
        p[a] = x;
    }
    return p;
}

Vec3 random_direction(std::mt19937& rng) {
    std::normal_distribution<float> g;
    for (;;) {
        const Vec3 d(g(rng), g(rng), g(rng));
        if (length(d) > 1e-3f) return normalize(d);
    }
}

/// Both slab tests of one ray against one node under one ISA.
struct BothTests {
    uint32_t exact = 0, fast = 0;  ///< lanes entered
    float exact_dist[8], fast_dist[8];
    bool fma = false;  ///< whether the fast test took the FMA path
};
BothTests run_both(Isa isa, const bvh8::TraceContext& ctx, const bvh8::Node& node, const Ray& ray) {
    const bvh8::KernelTable& k = bvh8::kernels_for(isa);
    BothTests b;
    uint32_t any = 0;
    b.exact = k.node_test(&node, 1, ray, ray.tmax, b.exact_dist, &any);
    b.fast = k.node_test_fast(ctx, &node, 1, ray, ray.tmax, b.fast_dist, &any, &b.fma);
    return b;
}

struct Outcome {
    size_t rays = 0, fma_rays = 0, exact_entered = 0, fma_only = 0, lanes = 0;
    /// The same counts where the origin and the ray's start lie within 1,000 box sizes of the
    /// box (near_scale): there the FMA test's widening, a few ulps of those distances, stays
    /// below a box's size.
    size_t near_exact_entered = 0, near_fma_only = 0;
};

/// The compressed form of the same: the traversal's test of a QNode (planes decoded, then the
/// FMA test) against the exact test of the decoded node.
BothTests run_compressed(Isa isa, const bvh8::TraceContext& ctx, const bvh8::QNode& q, const bvh8::Node& decoded,
                         const Ray& ray) {
    const bvh8::KernelTable& k = bvh8::kernels_for(isa);
    BothTests b;
    uint32_t any = 0;
    b.exact = k.node_test(&decoded, 1, ray, ray.tmax, b.exact_dist, &any);
    b.fast = k.node_test_compressed(ctx, &q, 1, ray, ray.tmax, b.fast_dist, &any, &b.fma);
    return b;
}

/// Throws rays at the boundaries of random nodes around `centre` from origins `distance` away.
/// `compressed`: the nodes are quantized, and rays aim at the decoded boxes.
void check_never_culls(const Vec3& centre, float size, float distance, unsigned seed, Outcome& out,
                       bool compressed = false) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> lane_pick(0, 7), tmax_pick(0, 3);
    const bool near_scale = length(centre) + distance <= 1e3f * size;
    for (int trial = 0; trial < (compressed ? 300 : 600); ++trial) {
        bvh8::Node node = node_near(rng, centre, size);
        bvh8::QNode q{};
        bvh8::TraceContext ctx;
        if (compressed) {
            q = bvh8::compress_nodes({&node, 1})[0];
            node = bvh8::decode_node(q);
            ctx.qnodes = &q;
            bvh8::set_plane_bounds(ctx, &q, 1);
        } else {
            bvh8::set_plane_bounds(ctx, &node, 1);  // the tightest bound: this node is the whole tree
        }
        const Vec3 target = boundary_point(rng, node, lane_pick(rng));
        Ray ray;
        ray.dir = random_direction(rng);
        ray.org = target - ray.dir * distance;
        ray.tmin = 0.0f;
        // The far end too: infinite, or just short of / beyond the target.
        const int tp = tmax_pick(rng);
        ray.tmax = tp == 0 ? kInfinity : distance * (tp == 1 ? 1.0f - 1e-6f : (tp == 2 ? 1.0f : 1.0f + 1e-6f));
        for (Isa isa : cpu_isas()) {
            const BothTests b = compressed ? run_compressed(isa, ctx, q, node, ray) : run_both(isa, ctx, node, ray);
            const uint32_t exact = b.exact, fast = b.fast;
            ++out.rays;
            out.fma_rays += b.fma;
            ASSERT_EQ(exact & ~fast, 0u) << isa_name(isa) << ": the FMA test culled a box the exact test enters"
                                         << " (centre " << centre.x << ", distance " << distance << ", trial " << trial
                                         << ")";
            for (int lane = 0; lane < 8; ++lane) {
                ++out.lanes;
                if (!((exact >> lane) & 1)) {
                    out.fma_only += (fast >> lane) & 1;
                    if (near_scale) out.near_fma_only += (fast >> lane) & 1;
                    continue;
                }
                ++out.exact_entered;
                out.near_exact_entered += near_scale;
                ASSERT_LE(b.fast_dist[lane], b.exact_dist[lane])
                    << isa_name(isa) << ": entry distance above the exact test's, trial " << trial;
            }
        }
    }
}

TEST(Bvh8FmaSlab, NeverCullsABoxTheExactTestEnters) {
    Outcome out;
    unsigned seed = 1;
    // Boxes near the origin and far from it; origins from just off the surface to a million box
    // sizes away (where -org * inv dominates the FMA's rounding).
    for (const Vec3 centre : {Vec3(0.0f), Vec3(1000.0f, -20.0f, 3.0f), Vec3(-3e5f, 2e5f, 7e4f), Vec3(1e-3f)})
        for (float size : {1e-3f, 1.0f, 100.0f})
            for (float distance_in_sizes : {1e-3f, 1.0f, 1e3f, 1e6f})
                check_never_culls(centre, size, size * distance_in_sizes, seed++, out);
    // The comparison means something: the FMA path ran for the rays, and boxes were entered and
    // missed. Its widening is a few ulps of the distance to the far side of the tree and of the
    // origin's magnitude (the exact test widens only the far planes by 2 gamma(3), with the slack
    // on the interval's ends), so a box of 1e-3 at 3e5 from the origin is entered by it alone;
    // within 1,000 box sizes it enters at most half again the exact test's lanes.
    EXPECT_EQ(out.fma_rays, out.rays);
    EXPECT_GT(out.exact_entered, out.lanes / 20);
    EXPECT_LT(out.exact_entered, out.lanes / 2);
    EXPECT_GT(out.near_exact_entered, 1000u);
    EXPECT_LT(out.near_fma_only, out.near_exact_entered / 2);
}

TEST(Bvh8FmaSlab, CompressedNodesNeverCullADecodedBoxTheExactTestEnters) {
    Outcome out;
    unsigned seed = 100;
    for (const Vec3 centre : {Vec3(0.0f), Vec3(1000.0f, -20.0f, 3.0f), Vec3(-3e5f, 2e5f, 7e4f), Vec3(1e-3f)})
        for (float size : {1e-3f, 1.0f, 100.0f})
            for (float distance_in_sizes : {1e-3f, 1.0f, 1e3f, 1e6f})
                check_never_culls(centre, size, size * distance_in_sizes, seed++, out, true);
    EXPECT_EQ(out.fma_rays, out.rays);
    EXPECT_GT(out.exact_entered, out.lanes / 20);
    EXPECT_GT(out.near_exact_entered, 500u);
    EXPECT_LT(out.near_fma_only, out.near_exact_entered / 2);
}

TEST(Bvh8FmaSlab, RaysItCannotBoundKeepTheExactTest) {
    std::mt19937 rng(5);
    const bvh8::Node node = node_near(rng, Vec3(0.0f), 1.0f);
    bvh8::TraceContext ctx;
    bvh8::set_plane_bounds(ctx, &node, 1);
    // An axis-parallel ray (1/dir infinite) and an origin so far that the bound would overflow.
    Ray parallel, far_away;
    parallel.org = Vec3(node.box[0][0][0], 0.0f, -10.0f), parallel.dir = Vec3(0.0f, 0.0f, 1.0f);
    far_away.org = Vec3(3e37f, 0.0f, 0.0f), far_away.dir = Vec3(-1.0f, 1e-30f, 1e-30f);
    for (const Ray& ray : {parallel, far_away})
        for (Isa isa : cpu_isas()) {
            const BothTests b = run_both(isa, ctx, node, ray);
            EXPECT_EQ(b.fast, b.exact) << isa_name(isa);
            EXPECT_FALSE(b.fma) << isa_name(isa);
        }
}

TEST(Bvh8FmaSlab, PlaneBoundsCoverEveryValidLaneAndSkipTheEmptyOnes) {
    std::mt19937 rng(9);
    bvh8::Node nodes[2] = {node_near(rng, Vec3(0.0f), 1.0f), node_near(rng, Vec3(50.0f), 2.0f)};
    nodes[1].valid = 0x7f;  // lane 7 empty: its box must not count
    nodes[1].box[0][0][7] = -1e30f;
    bvh8::TraceContext ctx;
    bvh8::set_plane_bounds(ctx, nodes, 2);
    for (const bvh8::Node& node : nodes)
        for (int lane = 0; lane < 8; ++lane) {
            if (!((node.valid >> lane) & 1)) continue;
            for (int a = 0; a < 3; ++a) {
                EXPECT_LE(ctx.plane_lo[a], node.box[a][0][lane]);
                EXPECT_GE(ctx.plane_hi[a], node.box[a][1][lane]);
            }
        }
    EXPECT_GT(ctx.plane_lo[0], -1e29f);
}

}  // namespace
}  // namespace thicket::bvh8_fma_slab_test
