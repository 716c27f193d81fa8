#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <unistd.h>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh/bvh.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"

namespace thicket::bvh_test {
namespace {

Scene soup() { return testing::nasty_scenes().back(); }

Bvh<Triangles<>> make_bvh(const Scene& scene, BvhBuilder builder, int max_leaf = 8) {
    BvhBuildOptions o;
    o.builder = builder;
    o.max_leaf = max_leaf;
    return Bvh<Triangles<>>(Triangles<>(scene.mesh), o);
}

TEST(BvhLayout, NodeIsThirtyTwoBytesAndPoolIsCacheAligned) {
    EXPECT_EQ(sizeof(BvhNode), 32u);
    const Scene scene = soup();
    const auto bvh = make_bvh(scene, BvhBuilder::BinnedSah);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(bvh.data().nodes.data()) % 64, 0u);
    // Allocated once for 2N nodes; only the pairs in use are ever written (and so touched).
    EXPECT_EQ(bvh.data().nodes.capacity(), 2 * scene.primitive_count()) << "pool allocated once, 2N nodes";
    EXPECT_LE(bvh.data().nodes_used, 2 * scene.primitive_count());
}

TEST(BvhBuild, EveryBuilderMakesAValidTreeWithTightBounds) {
    const Scene scene = soup();
    for (BvhBuilder b : {BvhBuilder::Midpoint, BvhBuilder::BinnedSah, BvhBuilder::SweepSah, BvhBuilder::Lbvh}) {
        for (int max_leaf : {1, 4, 8}) {
            const auto bvh = make_bvh(scene, b, max_leaf);
            const BvhData& d = bvh.data();
            ASSERT_NO_THROW(validate_bvh(d, scene.primitive_count()));
            const BvhFigures f = bvh_figures(d);
            EXPECT_LE(f.max_leaf_size, size_t(max_leaf)) << "leaves never exceed max-leaf";
            EXPECT_EQ(f.nodes, d.nodes_used - 1) << "every node but the unused slot 1 is reachable";
            // Each node's box is exactly the union of its primitives' boxes.
            for (uint32_t n = 0; n < d.nodes_used; ++n) {
                if (n == 1) continue;
                const BvhNode& node = d.nodes[n];
                Aabb want;
                if (node.is_leaf()) {
                    for (uint32_t i = 0; i < node.count; ++i) want.grow(bvh.primitives().bounds(d.prim_indices[node.leftFirst + i]));
                } else {
                    want.grow(d.nodes[node.leftFirst].bounds());
                    want.grow(d.nodes[node.leftFirst + 1].bounds());
                }
                EXPECT_EQ(node.aabbMin, want.min);
                EXPECT_EQ(node.aabbMax, want.max);
            }
        }
    }
}

TEST(BvhBuild, SahBuildersBeatMidpointOnClusteredGeometry) {
    // Dense clusters far apart: the midpoint split wastes levels on empty space, the SAH does not.
    TriangleMesh m;
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 4000; ++i) {
        const Vec3 c = (i % 4 == 0 ? Vec3(0.0f) : Vec3(100.0f)) + Vec3(u(rng), u(rng), u(rng)) * (i % 2 ? 1.0f : 5.0f);
        const auto base = uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {c, c + Vec3(0.05f, 0, 0), c + Vec3(0, 0.05f, 0.01f)});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    Scene scene;
    scene.mesh = m;
    const double midpoint = bvh_figures(make_bvh(scene, BvhBuilder::Midpoint).data()).sah_cost;
    const double binned = bvh_figures(make_bvh(scene, BvhBuilder::BinnedSah).data()).sah_cost;
    const double sweep = bvh_figures(make_bvh(scene, BvhBuilder::SweepSah).data()).sah_cost;
    EXPECT_LT(binned, midpoint);
    EXPECT_LT(sweep, midpoint);
    EXPECT_LE(sweep, binned * 1.02) << "the full sweep is at least about as good as 8 bins";
}

TEST(BvhBuild, IdenticalCentroidsStayShallow) {
    for (const Scene& scene : testing::nasty_scenes()) {
        for (BvhBuilder b : {BvhBuilder::Midpoint, BvhBuilder::BinnedSah, BvhBuilder::SweepSah, BvhBuilder::Lbvh}) {
            const auto bvh = make_bvh(scene, b, 1);
            EXPECT_LE(bvh_figures(bvh.data()).max_depth, size_t(kMaxDepth)) << scene.name;
        }
    }
}

TEST(BvhBuild, LbvhSplitsWhereTheHighestMortonBitChanges) {
    // Small triangles at the centres of a 4x4x4 grid of cells: the first code bit is x's top bit,
    // then y's, then z's, so the root splits x at the middle, its children y, their children z.
    TriangleMesh m;
    for (int x = 0; x < 4; ++x)
        for (int y = 0; y < 4; ++y)
            for (int z = 0; z < 4; ++z) {
                const Vec3 c{float(x), float(y), float(z)};
                const auto base = uint32_t(m.positions.size());
                m.positions.insert(m.positions.end(), {c, c + Vec3(0.1f, 0, 0), c + Vec3(0, 0.1f, 0)});
                m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
            }
    Scene scene;
    scene.mesh = m;
    const auto bvh = make_bvh(scene, BvhBuilder::Lbvh, 1);
    const BvhData& d = bvh.data();
    ASSERT_NO_THROW(validate_bvh(d, scene.primitive_count()));
    EXPECT_EQ(bvh_figures(d).max_leaf_size, 1u);
    // Children (left, right) of node n are separated on `axis`: left's max below right's min.
    auto expect_split = [&](uint32_t n, int axis) {
        ASSERT_FALSE(d.nodes[n].is_leaf());
        const BvhNode& l = d.nodes[d.nodes[n].leftFirst];
        const BvhNode& r = d.nodes[d.nodes[n].leftFirst + 1];
        EXPECT_EQ(l.count + r.count, 0u) << "64 cells: the top three levels are interior";
        EXPECT_LT(l.aabbMax[axis], r.aabbMin[axis]) << "node " << n << " axis " << axis;
        EXPECT_EQ(ChildOrder::split_axis(d.child_order[n]), axis);
    };
    expect_split(0, 0);
    for (uint32_t c : {d.nodes[0].leftFirst, d.nodes[0].leftFirst + 1}) {
        expect_split(c, 1);
        for (uint32_t g : {d.nodes[c].leftFirst, d.nodes[c].leftFirst + 1}) expect_split(g, 2);
    }
}

class SavedBvh : public ::testing::Test {
protected:
    void SetUp() override {
        scene_ = soup();
        accel_ = build_accel("bvh:builder=sweep-sah,traversal=ordered-axis", scene_);
        path_ = (std::filesystem::temp_directory_path() / ("thicket-bvh-test-" + std::to_string(::getpid()) + ".bvh")).string();
        save_accel(*accel_, scene_, path_);
        std::ifstream in(path_, std::ios::binary);
        bytes_.assign(std::istreambuf_iterator<char>(in), {});
    }
    void TearDown() override { std::filesystem::remove(path_); }

    void write(const std::string& bytes) {
        std::ofstream out(path_, std::ios::binary | std::ios::trunc);
        out << bytes;
    }
    std::string load_error(const Scene& scene) {
        try {
            load_accel(path_, scene);
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    }

    Scene scene_;
    std::unique_ptr<Accel> accel_;
    std::string path_, bytes_;
};

TEST_F(SavedBvh, LoadsBackWithIdenticalHits) {
    auto loaded = load_accel(path_, scene_);
    EXPECT_EQ(loaded->spec(), accel_->spec());
    for (const Ray& r : testing::conformance_rays(scene_, 2000)) {
        const Hit a = accel_->intersect(r), b = loaded->intersect(r);
        ASSERT_EQ(a.prim, b.prim);
        ASSERT_EQ(a.t, b.t);
        ASSERT_EQ(accel_->occluded(r), loaded->occluded(r));
    }
    EXPECT_EQ(loaded->stats().nodes, accel_->stats().nodes);
}

TEST_F(SavedBvh, RefusesCorruptTruncatedForeignAndOtherVersionFiles) {
    std::string corrupt = bytes_;
    corrupt[corrupt.size() / 2] ^= 0x40;
    write(corrupt);
    EXPECT_NE(load_error(scene_).find("checksum"), std::string::npos) << load_error(scene_);

    write(bytes_.substr(0, bytes_.size() - 7));
    EXPECT_NE(load_error(scene_).find("truncated"), std::string::npos) << load_error(scene_);

    write(bytes_.substr(0, 10));
    EXPECT_NE(load_error(scene_).find(path_), std::string::npos) << "errors name the file";

    std::string version = bytes_;
    version[8] = 99;
    write(version);
    EXPECT_NE(load_error(scene_).find("version 99"), std::string::npos) << load_error(scene_);

    write("PK\x03\x04 not a bvh at all");
    EXPECT_NE(load_error(scene_).find("not a thicket structure file"), std::string::npos);

    write(bytes_);
    Scene other = scene_;
    other.mesh.positions[0].x += 1.0f;
    EXPECT_NE(load_error(other).find("another scene"), std::string::npos) << load_error(other);
    EXPECT_EQ(load_error(scene_), "");
}

TEST_F(SavedBvh, StructurallyBrokenPayloadIsRefusedNotTraversed) {
    // Re-save a BVH whose child index points backwards (a cycle); the checksum is valid, so the
    // structural validation must catch it.
    BvhData broken = static_cast<const Bvh<Triangles<>>&>(*accel_).data();
    broken.nodes[broken.nodes[0].leftFirst].leftFirst = 0;
    broken.nodes[broken.nodes[0].leftFirst].count = 0;
    EXPECT_THROW(validate_bvh(broken, scene_.primitive_count()), Error);
}

TEST(BvhStats, ReportsTheFiguresTheIssueAsksFor) {
    const Scene scene = soup();
    auto accel = build_accel("bvh", scene);
    const AccelStats s = accel->stats();
    EXPECT_EQ(s.primitives, scene.primitive_count());
    EXPECT_GT(s.nodes, 1u);
    EXPECT_EQ(s.nodes, 2 * s.leaves - 1) << "a binary tree";
    EXPECT_GT(s.max_depth, 3u);
    EXPECT_GE(s.bytes, s.nodes * 32);
    EXPECT_GT(s.sah_cost, 1.0);
    EXPECT_EQ(s.primitive_bytes, scene.primitive_count() * 36);
}

}  // namespace
}  // namespace thicket::bvh_test
