// The crossings of double rays (query/crossings_double.h): a millimetre stack of quads 1e7 from
// the origin, which float rounds onto one plane, is crossed once per quad, in order, a ray through
// a shared diagonal crossing once; the batch forms lay the lists out as HitLists does.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "thicket/query/double_rays.h"
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

// The float64 batch (query/double_rays.h) from rows: a row without a meaning answers a miss and
// is counted; rows of 6 take the interval given beside them.
TEST(CrossingsDouble, BatchFormsLayOutTheListsAndSkipInvalidRows) {
    const Scene scene = quad_stack();
    const auto accel = build_accel("bvh:precision=double", scene);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> rows = {
        kO + 0.4, kO + 0.3, kO - 1.0, 0, 0, 1,  0, kInf,  //
        kO + 0.4, nan,      kO - 1.0, 0, 0, 1,  0, kInf,  // no meaning
        kO + 0.4, kO + 0.3, kO + 1.0, 0, 0, -1, 0, kInf,  //
        kO + 5.0, kO + 0.3, kO - 1.0, 0, 0, 1,  0, kInf};  // beside the stack
    const RayBatchD batch = make_rays(RayRowsD{rows.data(), 4, 8}, 2);
    EXPECT_EQ(batch.valid, (std::vector<uint8_t>{1, 0, 1, 1}));
    BatchOptions options;
    options.threads = 2;
    std::vector<uint32_t> counts(batch.size());
    EXPECT_EQ(crossing_counts(*accel, batch, counts, options), 1u);
    EXPECT_EQ(counts, (std::vector<uint32_t>{3, 0, 3, 0}));
    const HitListsD lists = crossing_lists(*accel, batch, counts, options);
    EXPECT_EQ(lists.splits, (std::vector<size_t>{0, 3, 3, 6, 6}));
    ASSERT_EQ(lists.hits.size(), 6u);
    // From above, the top layer comes first.
    EXPECT_EQ(lists.hits[3].prim / 2, 2u);
    EXPECT_EQ(lists.hits[5].prim / 2, 0u);
    for (size_t j = 1; j < 3; ++j) EXPECT_LT(lists.hits[j - 1].t, lists.hits[j].t);

    std::vector<HitD> hits(batch.size());
    EXPECT_EQ(closest_hits(*accel, batch, hits, options), 1u);
    EXPECT_EQ(hits[0].t, lists.hits[0].t);
    EXPECT_FALSE(hits[1].found());
    EXPECT_FALSE(hits[3].found());
    std::vector<uint8_t> occluded(batch.size(), 7);
    EXPECT_EQ(occlusions(*accel, batch, occluded, options), 1u);
    EXPECT_EQ(occluded, (std::vector<uint8_t>{1, 0, 1, 0}));

    // Rows of 6 with the interval beside them: a tmax short of the second layer crosses one.
    const std::vector<double> six = {kO + 0.4, kO + 0.3, kO - 1.0, 0, 0, 1};
    RayRowsD short_rows{six.data(), 1, 6};
    short_rows.tmax = 1.0005;
    std::vector<uint32_t> one(1);
    crossing_counts(*accel, make_rays(short_rows), one);
    EXPECT_EQ(one[0], 1u);
    EXPECT_THROW(make_rays(RayRowsD{six.data(), 1, 7}), Error);
}

TEST(CrossingsDouble, FloatStructuresRefuseNamingTheOption) {
    const auto accel = build_accel("bvh", quad_stack());
    try {
        count_hits_double(*accel, RayD{{kO + 0.4, kO + 0.3, kO - 1.0}, 0.0, {0, 0, 1}, kInf});
        ADD_FAILURE() << "a float structure counted double crossings";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("precision=double"), std::string::npos) << e.what();
    }
    // The batch is refused before anything is traced, with the one message, naming both double
    // structures from the registry.
    const std::vector<double> row = {kO + 0.4, kO + 0.3, kO - 1.0, 0, 0, 1, 0, kInf};
    std::vector<HitD> hits(1);
    try {
        closest_hits(*accel, make_rays(RayRowsD{row.data(), 1, 8}), hits);
        ADD_FAILURE() << "a float structure traced a float64 batch";
    } catch (const Error& e) {
        const std::string what = e.what();
        for (const char* needle :
             {"float64 rays are traced", "bvh:precision=double", "brute:precision=double", "structure 'bvh:"})
            EXPECT_NE(what.find(needle), std::string::npos) << what;
    }
}

}  // namespace
}  // namespace thicket::testing::crossings_double_test
