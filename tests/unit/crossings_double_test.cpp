// The crossings of double rays (accel/crossings_double.h): a millimetre stack of quads 1e7 from
// the origin, which float rounds onto one plane, is crossed once per quad, in order, a ray through
// a shared diagonal crossing once; the batch forms lay the lists out as HitLists does.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "thicket/accel/crossings_double.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/scene/scene.h"

namespace thicket::testing::crossings_double_test {
namespace {

constexpr double kO = 1e7;
constexpr double kInf = std::numeric_limits<double>::infinity();

/// Three quads over [kO + 0.2, kO + 0.8]^2 (two triangles each, split along the diagonal x = y) at
/// z = kO, kO + 1 mm and kO + 2 mm, their vertices kept in double. A ray rounded to float (spacing 1
/// here) starts at a whole coordinate, beside them.
Scene quad_stack() {
    TriangleMesh mesh;
    for (int layer = 0; layer < 3; ++layer) {
        const double z = kO + 0.001 * layer;
        const uint32_t first = uint32_t(mesh.positions_double.size());
        const double corners[4][2] = {{0.2, 0.2}, {0.8, 0.2}, {0.8, 0.8}, {0.2, 0.8}};
        for (const auto& c : corners) mesh.positions_double.push_back({kO + c[0], kO + c[1], z});
        mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
    }
    for (const Vec3d& p : mesh.positions_double) mesh.positions.push_back(p.to_float());
    Scene scene;
    scene.name = "millimetre quad stack at 1e7";
    scene.add_mesh(mesh);
    return scene;
}

TEST(CrossingsDouble, MillimetreLayersAreCrossedOnceEachInOrder) {
    const Scene scene = quad_stack();
    for (const char* spec : {"bvh:precision=double", "brute:precision=double"}) {
        SCOPED_TRACE(spec);
        const auto accel = build_accel(spec, scene);
        // Through the middle of one triangle of each quad, and through the shared diagonal.
        for (const double at : {0.3, 0.5}) {
            const RayD ray{{kO + at + (at == 0.5 ? 0.0 : 0.1), kO + at, kO - 1.0}, 0.0, {0, 0, 1}, kInf};
            std::vector<HitD> hits;
            all_hits_double(*accel, ray, hits);
            ASSERT_EQ(hits.size(), 3u) << "at " << at;
            for (int layer = 0; layer < 3; ++layer) EXPECT_NEAR(hits[layer].t, 1.0 + 0.001 * layer, 1e-9);
            EXPECT_EQ(count_hits_double(*accel, ray), 3u);
        }
        // The interval bounds the crossings: [0, 1.0015] holds the first two layers only.
        EXPECT_EQ(count_hits_double(*accel, RayD{{kO + 0.4, kO + 0.3, kO - 1.0}, 0.0, {0, 0, 1}, 1.0015}), 2u);
        EXPECT_EQ(count_hits_double(*accel, RayD{{kO + 0.4, kO + 0.3, kO - 1.0}, 1.0005, {0, 0, 1}, kInf}), 2u);
    }
    // What float makes of the same stack: one plane.
    const Ray rounded{Vec3{float(kO + 0.4), float(kO + 0.3), float(kO - 1.0)}, 0.0f, Vec3{0, 0, 1}, kInfinity};
    EXPECT_LT(build_accel("bvh", scene)->count_hits(rounded), 3u);
}

TEST(CrossingsDouble, BatchFormsLayOutTheListsAndSkipInvalidRays) {
    const Scene scene = quad_stack();
    const auto accel = build_accel("bvh:precision=double", scene);
    const std::vector<RayD> rays = {{{kO + 0.4, kO + 0.3, kO - 1.0}, 0.0, {0, 0, 1}, kInf},
                                    {{kO + 0.4, kO + 0.3, kO - 1.0}, 0.0, {0, 0, 1}, kInf},  // marked invalid
                                    {{kO + 0.4, kO + 0.3, kO + 1.0}, 0.0, {0, 0, -1}, kInf},
                                    {{kO + 5.0, kO + 0.3, kO - 1.0}, 0.0, {0, 0, 1}, kInf}};  // beside the stack
    const std::vector<uint8_t> valid = {1, 0, 1, 1};
    std::vector<uint32_t> counts(rays.size());
    count_hits_double(*accel, rays, valid, counts, 2);
    EXPECT_EQ(counts, (std::vector<uint32_t>{3, 0, 3, 0}));
    const HitListsD lists = list_hits_double(*accel, rays, valid, counts, 2);
    EXPECT_EQ(lists.splits, (std::vector<size_t>{0, 3, 3, 6, 6}));
    ASSERT_EQ(lists.hits.size(), 6u);
    // From above, the top layer comes first.
    EXPECT_EQ(lists.hits[3].prim / 2, 2u);
    EXPECT_EQ(lists.hits[5].prim / 2, 0u);
    for (size_t j = 1; j < 3; ++j) EXPECT_LT(lists.hits[j - 1].t, lists.hits[j].t);
}

TEST(CrossingsDouble, FloatStructuresRefuseNamingTheOption) {
    const auto accel = build_accel("bvh", quad_stack());
    try {
        count_hits_double(*accel, RayD{{kO + 0.4, kO + 0.3, kO - 1.0}, 0.0, {0, 0, 1}, kInf});
        ADD_FAILURE() << "a float structure counted double crossings";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("precision=double"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace thicket::testing::crossings_double_test
