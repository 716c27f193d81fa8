// bvh8:nodes=compressed (include/thicket/bvh8/compress.h): every decoded box contains the exact
// box it stands for, on adversarial nodes (tiny, flat, huge, far from the origin, one lane) and
// on a built tree; quantization is tight (within a step of the exact plane), not merely outward;
// what cannot be held is refused by name; infinite and NaN planes hold every finite point. The traversal's answers are the conformance suite's
// (variants bvh8:isa=<each>,nodes=compressed against brute force). The grid is the finest that
// spans each node (the least sufficient exponent, worked in the test).
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "support/test_scenes.h"
#include "thicket/bvh8/bvh8.h"
#include "thicket/bvh8/compress.h"
#include "thicket/core/error.h"

namespace thicket::bvh8_compress_test {
namespace {

/// A node of `lanes` valid boxes of extents from size * 1e-6 to size around `centre`.
bvh8::Node random_node(std::mt19937& rng, float centre, float size, int lanes) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), decade(-6.0f, 0.0f);
    bvh8::Node node{};
    for (int lane = 0; lane < bvh8::kWidth; ++lane) {
        for (int a = 0; a < 3; ++a) {
            node.box[a][0][lane] = INFINITY;
            node.box[a][1][lane] = -INFINITY;
        }
        if (lane >= lanes) continue;
        node.valid |= 1u << lane;
        node.child[lane] = uint32_t(lane * 1000);
        node.leaf_size[lane] = uint8_t(lane);
        for (int a = 0; a < 3; ++a) {
            const float lo = centre + unit(rng) * size;
            node.box[a][0][lane] = lo;
            node.box[a][1][lane] = lo + size * std::pow(10.0f, decade(rng));
        }
    }
    return node;
}

/// Checks that q's decoded lanes contain node's, lie within a step (2^e, plus the float's own
/// rounding) of them unless `tight` is false, and keep children, leaf sizes and the valid mask.
void expect_contains(const bvh8::Node& node, const bvh8::QNode& q, const std::string& where, bool tight = true) {
    const bvh8::Node d = bvh8::decode_node(q);
    ASSERT_EQ(d.valid, node.valid) << where;
    for (int lane = 0; lane < bvh8::kWidth; ++lane) {
        if (!((node.valid >> lane) & 1u)) continue;
        EXPECT_EQ(d.child[lane], node.child[lane]) << where;
        EXPECT_EQ(d.leaf_size[lane], node.leaf_size[lane]) << where;
        for (int a = 0; a < 3; ++a) {
            const float lo = node.box[a][0][lane], hi = node.box[a][1][lane];
            const float step = std::ldexp(1.0f, q.exponent[a]);
            const float slack = step + 2.0f * std::fabs(std::nextafter(hi, INFINITY) - hi) + 1e-38f;
            EXPECT_LE(d.box[a][0][lane], lo) << where << " lane " << lane << " axis " << a;
            EXPECT_GE(d.box[a][1][lane], hi) << where << " lane " << lane << " axis " << a;
            if (!tight) continue;
            EXPECT_LE(lo - d.box[a][0][lane], slack) << where << " lane " << lane << " axis " << a;
            EXPECT_LE(d.box[a][1][lane] - hi, slack) << where << " lane " << lane << " axis " << a;
        }
    }
}

/// How often a node's axis took the smallest sufficient exponent, or one more.
struct ExponentTally {
    size_t axes = 0, one_above = 0;
};

/// The exponent each finite axis of `node` needs at the least, worked here rather than read from
/// the code: the smallest e >= -126 whose 255 steps span [smallest lower plane, largest upper
/// plane]. The code may take one more where decoding in float falls short of the top plane (rare);
/// a looser grid (a slower-but-correct mutant: larger boxes, more nodes entered) fails here.
void expect_smallest_exponent(const bvh8::Node& node, const bvh8::QNode& q, const std::string& where,
                              ExponentTally& tally) {
    for (int a = 0; a < 3; ++a) {
        double lo = INFINITY, hi = -INFINITY;
        for (int lane = 0; lane < bvh8::kWidth; ++lane) {
            if (!((node.valid >> lane) & 1u)) continue;
            lo = std::min(lo, double(node.box[a][0][lane]));
            hi = std::max(hi, double(node.box[a][1][lane]));
        }
        if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
        int least = -126;
        while (255.0 * std::ldexp(1.0, least) < hi - lo) ++least;
        ++tally.axes;
        EXPECT_GE(q.exponent[a], least) << where << " axis " << a << ": a grid too fine to span the node";
        EXPECT_LE(q.exponent[a], least + 1) << where << " axis " << a << ": a grid coarser than needed";
        tally.one_above += q.exponent[a] == least + 1 ? 1 : 0;
    }
}

TEST(Bvh8Compress, DecodedBoxesContainTheExactOnesWithinAStep) {
    std::mt19937 rng(7);
    ExponentTally tally;
    const float centres[] = {0.0f, 1.0f, -3.5f, 1e4f, -1e7f, 3e12f, 1e-20f};
    const float sizes[] = {1.0f, 1e-3f, 1e-9f, 1e3f, 1e20f, 1e-30f};
    for (float centre : centres)
        for (float size : sizes)
            for (int lanes : {1, 2, 5, 8}) {
                for (int k = 0; k < 20; ++k) {
                    const bvh8::Node node = random_node(rng, centre, size, lanes);
                    const bvh8::QNodes q = bvh8::compress_nodes({&node, 1});
                    const std::string where = "centre " + std::to_string(centre) + " size " + std::to_string(size);
                    expect_contains(node, q[0], where);
                    expect_smallest_exponent(node, q[0], where, tally);
                    if (HasFatalFailure() || HasFailure()) return;
                }
            }
    std::printf("[ exponent ] %zu of %zu axes took one step more than the least sufficient exponent\n",
                tally.one_above, tally.axes);
    EXPECT_LE(tally.one_above, tally.axes / 50);
}

TEST(Bvh8Compress, FlatAndPointBoxesAndTheLargestFloats) {
    bvh8::Node node{};
    for (int lane = 0; lane < bvh8::kWidth; ++lane)
        for (int a = 0; a < 3; ++a) node.box[a][0][lane] = INFINITY, node.box[a][1][lane] = -INFINITY;
    node.valid = 0x7;
    for (int a = 0; a < 3; ++a) {
        node.box[a][0][0] = node.box[a][1][0] = 2.5f;  // a point
        node.box[a][0][1] = -3.4e38f;                   // the whole float range
        node.box[a][1][1] = 3.4e38f;
        node.box[a][0][2] = 1e-40f;                      // subnormal planes
        node.box[a][1][2] = 3e-40f;
    }
    // A node spanning the whole float range: 255 steps of 2^122 pass FLT_MAX, so upper planes may
    // decode to +inf: still containing, never tight.
    const bvh8::QNodes q = bvh8::compress_nodes({&node, 1});
    expect_contains(node, q[0], "flat/huge/subnormal", false);
    bvh8::Node small = node;
    for (int a = 0; a < 3; ++a) small.box[a][0][1] = -1e3f, small.box[a][1][1] = 1e3f;
    expect_contains(small, bvh8::compress_nodes({&small, 1})[0], "flat/subnormal");
    // A node whose every box is one point decodes exactly.
    bvh8::Node point = node;
    point.valid = 0x1;
    const bvh8::Node d = bvh8::decode_node(bvh8::compress_nodes({&point, 1})[0]);
    for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(d.box[a][0][0], 2.5f);
        EXPECT_EQ(d.box[a][1][0], 2.5f);
    }
}

TEST(Bvh8Compress, RefusesWhatTheChildWordOrAFloatGridCannotHold) {
    std::mt19937 rng(3);
    bvh8::Node node = random_node(rng, 0.0f, 1.0f, 3);
    node.child[2] = 1u << bvh8::kQIndexBits;
    try {
        bvh8::compress_nodes({&node, 1});
        FAIL() << "a child index past 2^24 was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("nodes=full"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("lane 2"), std::string::npos) << e.what();
    }
}

TEST(Bvh8Compress, InfiniteAndNanPlanesSpanEveryFiniteValue) {
    std::mt19937 rng(5);
    bvh8::Node node = random_node(rng, 0.0f, 1.0f, 4);
    node.box[1][1][0] = INFINITY;
    node.box[1][0][1] = -INFINITY;
    node.box[1][0][2] = NAN;
    node.box[1][1][3] = NAN;
    const bvh8::Node d = bvh8::decode_node(bvh8::compress_nodes({&node, 1})[0]);
    EXPECT_EQ(d.box[1][1][0], INFINITY);
    EXPECT_EQ(d.box[1][0][1], -FLT_MAX);
    EXPECT_EQ(d.box[1][0][2], -FLT_MAX);
    EXPECT_EQ(d.box[1][1][3], INFINITY);
    for (int lane = 0; lane < 4; ++lane) {
        // The finite planes of that axis, and every plane of the others, still contain.
        if (std::isfinite(node.box[1][0][lane])) {
            EXPECT_LE(d.box[1][0][lane], node.box[1][0][lane]);
        }
        if (std::isfinite(node.box[1][1][lane])) {
            EXPECT_GE(d.box[1][1][lane], node.box[1][1][lane]);
        }
        for (int a : {0, 2}) {
            EXPECT_LE(d.box[a][0][lane], node.box[a][0][lane]);
            EXPECT_GE(d.box[a][1][lane], node.box[a][1][lane]);
        }
    }
}

TEST(Bvh8Compress, BuiltTreeDecodesAroundTheFullTreeAndSavesEnclosingBoxes) {
    const Scene scene = testing::nasty_scenes().back();
    Bvh8Options full_options, compressed_options;
    compressed_options.compressed = true;
    const Bvh8<Triangles<>> full(Triangles<>(scene.mesh), full_options);
    const Bvh8<Triangles<>> compressed(Triangles<>(scene.mesh), compressed_options);
    const auto& nodes = full.tree().nodes;
    const bvh8::QNodes& q = compressed.qnodes();
    ASSERT_GT(nodes.size(), 1u);
    ASSERT_EQ(q.size(), nodes.size());  // the same build, node for node
    EXPECT_TRUE(compressed.tree().nodes.empty()) << "the full nodes are freed";
    for (size_t k = 0; k < nodes.size(); ++k) expect_contains(nodes[k], q[k], "node " + std::to_string(k));
    const AccelStats fs = full.stats(), cs = compressed.stats();
    EXPECT_EQ(fs.bytes - cs.bytes, nodes.size() * (sizeof(bvh8::Node) - sizeof(bvh8::QNode)));
    // What is saved: each lane encloses its child node's decoded lanes (the load proof's rule).
    AlignedVector<bvh8::Node, 64> saved;
    bvh8::decode_nodes(q, saved);
    for (const bvh8::Node& n : saved)
        for (int lane = 0; lane < bvh8::kWidth; ++lane) {
            if (!((n.valid >> lane) & 1u) || n.leaf_size[lane] != 0) continue;
            const bvh8::Node& c = saved[n.child[lane]];
            for (int cl = 0; cl < bvh8::kWidth; ++cl) {
                if (!((c.valid >> cl) & 1u)) continue;
                for (int a = 0; a < 3; ++a) {
                    EXPECT_LE(n.box[a][0][lane], c.box[a][0][cl]);
                    EXPECT_GE(n.box[a][1][lane], c.box[a][1][cl]);
                }
            }
        }
}

}  // namespace
}  // namespace thicket::bvh8_compress_test
