// The library's point queries (query/point_queries.h) and its rows-to-answers path
// (query/ray_rows.h), which the CLI and the Python module call: judged against analytic
// inside/outside on non-convex closed meshes, against brute force, and against make_ray().
#include <gtest/gtest.h>

#include <atomic>
#include <functional>
#include <cmath>
#include <iterator>
#include <limits>
#include <random>
#include <vector>

#include "thicket/query/point_queries.h"
#include "thicket/query/ray_rows.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "support/probe.h"

namespace point_queries_test {

using namespace thicket;

namespace {

constexpr float kPi = 3.14159265358979f;

/// A closed torus around the z axis: ring radius R, tube radius r, `around` x `tube` quads.
Scene torus_scene(float R, float r, int around, int tube) {
    TriangleMesh mesh;
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < tube; ++j) {
            const float a = 2 * kPi * float(i) / float(around), b = 2 * kPi * float(j) / float(tube);
            mesh.positions.push_back({(R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b)});
        }
    auto at = [&](int i, int j) { return uint32_t((i % around) * tube + (j % tube)); };
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < tube; ++j) {
            const uint32_t q[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
            mesh.indices.insert(mesh.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        }
    Scene scene;
    scene.add_mesh(mesh);
    return scene;
}

/// The 12 triangles of the closed box [-h, h]^3.
void add_box(TriangleMesh& mesh, float h) {
    const uint32_t base = uint32_t(mesh.positions.size());
    for (int k = 0; k < 8; ++k) mesh.positions.push_back({k & 1 ? h : -h, k & 2 ? h : -h, k & 4 ? h : -h});
    const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces)
        for (uint32_t t : {f[0], f[1], f[2], f[0], f[2], f[3]}) mesh.indices.push_back(base + t);
}

/// Signed distance of p to the analytic torus (negative inside).
float torus_field(const Vec3& p, float R, float r) {
    const float ring = std::sqrt(p.x * p.x + p.y * p.y) - R;
    return std::sqrt(ring * ring + p.z * p.z) - r;
}

std::vector<Vec3> random_points(size_t n, float extent, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-extent, extent);
    std::vector<Vec3> points(n);
    for (Vec3& p : points) p = {u(rng), u(rng), u(rng)};
    return points;
}

}  // namespace

TEST(PointQueries, OccupancyOfATorusIsTheAnalyticInsideForEveryVoteCount) {
    const float R = 1.0f, r = 0.4f;
    const Scene scene = torus_scene(R, r, 96, 48);
    std::vector<Vec3> points;
    for (const Vec3& p : random_points(4000, 1.6f, 7))
        if (std::fabs(torus_field(p, R, r)) > 0.02f) points.push_back(p);  // clear of the tessellation's chords
    size_t inside_count = 0;
    for (const char* spec : {"bvh8", "kdtree", "grid"}) {
        const auto accel = build_accel(spec, scene);
        const PointQueries queries(*accel, scene);
        for (int samples : {1, 3, 5}) {
            std::vector<uint8_t> inside(points.size());
            queries.occupancy(points, inside, samples);
            inside_count = 0;
            for (size_t i = 0; i < points.size(); ++i) {
                ASSERT_EQ(inside[i], torus_field(points[i], R, r) < 0 ? 1 : 0)
                    << spec << " nsamples=" << samples << " point " << points[i].x << " " << points[i].y << " "
                    << points[i].z;
                inside_count += inside[i];
            }
        }
    }
    // The hole and the outside are both represented, and so is the tube.
    EXPECT_GT(inside_count, 50u);
    EXPECT_LT(inside_count, points.size() - 50);
}

TEST(PointQueries, NestedShellsAreInsideOnlyBetweenThem) {
    // Two closed boxes, one in the other: a ray from inside the inner box crosses twice (even:
    // outside, the hollow), from between them once.
    TriangleMesh mesh;
    add_box(mesh, 1.0f);
    add_box(mesh, 0.5f);
    Scene scene;
    scene.add_mesh(mesh);
    const auto accel = build_accel("bvh", scene);
    const PointQueries queries(*accel, scene);
    const std::vector<Vec3> points = {{0, 0, 0}, {0.1f, -0.2f, 0.3f}, {0.75f, 0, 0}, {0, -0.8f, 0.1f}, {0.6f, 0.6f, 0.6f},
                                      {1.5f, 0, 0}, {0, 0, -3}};
    const uint8_t want[] = {0, 0, 1, 1, 1, 0, 0};
    for (int samples : {1, 3, 5}) {
        std::vector<uint8_t> inside(points.size());
        queries.occupancy(points, inside, samples);
        for (size_t i = 0; i < points.size(); ++i) EXPECT_EQ(inside[i], want[i]) << "point " << i << " nsamples=" << samples;
    }
    std::vector<float> sd(points.size());
    queries.signed_distances(points, sd, 3);
    EXPECT_NEAR(sd[0], 0.5f, 1e-5f);    // hollow centre: outside, 0.5 from the inner box
    EXPECT_NEAR(sd[2], -0.25f, 1e-5f);  // between the shells: inside, 0.25 from both
    EXPECT_NEAR(sd[5], 0.5f, 1e-5f);
}

TEST(PointQueries, SignedDistanceIsBruteForcesDistanceSignedByOccupancy) {
    const float R = 1.0f, r = 0.4f;
    const Scene scene = torus_scene(R, r, 48, 24);
    const std::vector<Vec3> points = random_points(600, 1.6f, 11);
    const auto brute = build_accel("brute", scene);
    const auto grid = build_accel("grid", scene);  // answers no closest points itself: the bvh8 fallback does
    const PointQueries queries(*grid, scene);
    EXPECT_NE(&queries.closest_accel(), grid.get());
    EXPECT_EQ(&queries.closest_accel(), &queries.closest_accel());  // built once
    std::vector<float> sd(points.size());
    std::vector<uint8_t> inside(points.size());
    std::vector<NearestPoint> closest(points.size());
    BatchOptions two;
    two.threads = 2;
    queries.signed_distances(points, sd, 3, two);
    queries.occupancy(points, inside, 3, two);
    queries.closest_points(points, closest, two);
    for (size_t i = 0; i < points.size(); ++i) {
        const NearestPoint want = brute->closest_point(points[i]);
        ASSERT_EQ(closest[i].prim, want.prim) << i;
        ASSERT_FLOAT_EQ(closest[i].distance, want.distance) << i;
        ASSERT_FLOAT_EQ(sd[i], inside[i] ? -want.distance : want.distance) << i;
        // Far from the surface the sign is the analytic one.
        if (std::fabs(torus_field(points[i], R, r)) > 0.05f) {
            ASSERT_EQ(sd[i] < 0, torus_field(points[i], R, r) < 0) << i;
        }
    }
}

TEST(PointQueries, RefusesBadSampleCountsAndFindsNonFinitePoints) {
    const Scene scene = torus_scene(1.0f, 0.4f, 8, 4);
    const auto accel = build_accel("bvh", scene);
    const PointQueries queries(*accel, scene);
    std::vector<Vec3> points = {{0, 0, 0}};
    std::vector<uint8_t> inside(1);
    for (int bad : {0, 2, 7, -1}) EXPECT_THROW(queries.occupancy(points, inside, bad), Error) << bad;
    std::vector<uint8_t> wrong_size(2);
    EXPECT_THROW(queries.occupancy(points, wrong_size, 1), Error);
    points.push_back({0, std::numeric_limits<float>::quiet_NaN(), 0});
    EXPECT_EQ(first_non_finite(points), 1u);
    EXPECT_EQ(first_non_finite(std::span<const Vec3>(points).first(1)), 1u);
}

TEST(RayRows, TheConversionAcceptsExactlyWhatMakeRayAccepts) {
    // Every combination of special values in each column, in rows of 8 and of 6.
    const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
    const float specials[] = {0.0f, -0.0f, 1.0f, -2.5f, inf, -inf, nan, std::numeric_limits<float>::max(), 1e-40f};
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> pick(0, int(std::size(specials)) - 1);
    // As given and reordered (accel/ray_order.h: blocks sorted by octant and origin, n above
    // kReorderMin): every row is a ray of exactly one chunk or a row without one, never both.
    for (const bool reorder : {false, true})
    for (size_t width : {size_t(8), size_t(6)}) {
        std::vector<float> data;
        const size_t n = 10000;  // several chunks and blocks, most chunks with rows without a ray
        for (size_t i = 0; i < n; ++i)
            for (size_t c = 0; c < width; ++c) data.push_back(rng() % 3 ? float(int(rng() % 5)) - 2.0f : specials[pick(rng)]);
        const RayRows rows{data.data(), n, width, 0.5f, 40.0f};
        std::vector<uint8_t> seen(n, 0), without(n, 0);
        std::atomic<size_t> sorted_chunks{0};
        for_each_ray_chunk(rows, 2, reorder ? 0.0 : INFINITY, [&](const RayChunk& c) {
            sorted_chunks += c.sorted != nullptr;
            c.for_each_row_without_ray([&](size_t row) { ++without[row]; });
            for (size_t k = 0; k < c.count; ++k) {
                const size_t row = c.row(k);
                const float* r = &data[width * row];
                const float full[8] = {r[0], r[1], r[2], r[3], r[4], r[5], width == 8 ? r[6] : 0.5f, width == 8 ? r[7] : 40.0f};
                Ray want;
                ASSERT_TRUE(make_ray(full, want)) << "row " << row;
                const Ray& got = c.rays.data[k];
                ASSERT_TRUE(got.org.x == want.org.x && got.org.y == want.org.y && got.org.z == want.org.z &&
                            got.dir.x == want.dir.x && got.dir.y == want.dir.y && got.dir.z == want.dir.z &&
                            got.tmin == want.tmin && got.tmax == want.tmax)
                    << "row " << row;
                ++seen[row];
            }
        });
        EXPECT_EQ(sorted_chunks != 0, reorder);
        size_t valid = 0;
        for (size_t i = 0; i < n; ++i) {
            const float* r = &data[width * i];
            const float full[8] = {r[0], r[1], r[2], r[3], r[4], r[5], width == 8 ? r[6] : 0.5f, width == 8 ? r[7] : 40.0f};
            Ray unused;
            ASSERT_EQ(seen[i] != 0, make_ray(full, unused)) << "row " << i << " width " << width;
            ASSERT_EQ(seen[i] + without[i], 1) << "row " << i << " width " << width << " reorder " << reorder;
            valid += seen[i];
        }
        EXPECT_GT(valid, n / 10);
        EXPECT_LT(valid, n - n / 10);
        // The whole-batch conversion agrees row for row.
        const RayBatch batch = make_rays(rows, 2);
        ASSERT_EQ(batch.rays.size(), valid);
        for (size_t k = 0; k < batch.rays.size(); ++k) EXPECT_TRUE(seen[batch.row_of(k)]);
    }
    float row[7] = {};
    EXPECT_THROW(make_rays(RayRows{row, 1, 7}, 1), Error);
}

TEST(RayRows, EveryQueryAnswersRowsAsTheStructureAnswersRays) {
    const Scene scene = torus_scene(1.0f, 0.4f, 32, 16);
    const auto accel = build_accel("bvh8", scene);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    const size_t n = 1000;
    std::vector<float> data;
    for (size_t i = 0; i < n; ++i) {
        const float row[8] = {u(rng), u(rng), 3.0f, u(rng) * 0.2f, u(rng) * 0.2f, -1.0f, 0.0f, i % 7 == 3 ? -1.0f : 100.0f};
        data.insert(data.end(), row, row + 8);  // every 7th row from the fourth has tmin > tmax: no ray
    }
    const RayRows rows{data.data(), n, 8};
    BatchOptions options;
    options.threads = 2;
    std::atomic<size_t> progressed{0};
    options.progress = [&](size_t done) { progressed += done; };
    std::vector<Hit> hits(n);
    std::vector<uint8_t> occluded(n);
    std::vector<uint32_t> counts(n);
    const size_t without = closest_hits(*accel, rows, hits, options);
    EXPECT_EQ(progressed, n);  // every row, with or without a ray
    options.progress = nullptr;
    EXPECT_EQ(occlusions(*accel, rows, occluded, options), without);
    EXPECT_EQ(crossing_counts(*accel, rows, counts, options), without);
    const HitLists lists = crossing_lists(*accel, rows, options);
    EXPECT_EQ(without, (n + 3) / 7);
    ASSERT_EQ(lists.splits.size(), n + 1);
    size_t found = 0;
    for (size_t i = 0; i < n; ++i) {
        Ray ray;
        const bool has_ray = make_ray(&data[8 * i], ray);
        const Hit want = has_ray ? accel->intersect(ray) : Hit{};
        EXPECT_EQ(hits[i].prim, want.prim) << i;
        if (want.found()) {
            EXPECT_EQ(hits[i].t, want.t) << i;
        } else {
            EXPECT_TRUE(std::isinf(hits[i].t)) << i;  // a miss is +inf, not the ray's tmax
        }
        EXPECT_EQ(occluded[i], has_ray && accel->occluded(ray) ? 1 : 0) << i;
        std::vector<Hit> crossings;
        if (has_ray) accel->all_hits(ray, crossings);
        EXPECT_EQ(counts[i], crossings.size()) << i;
        ASSERT_EQ(lists.splits[i + 1] - lists.splits[i], crossings.size()) << i;
        for (size_t j = 0; j < crossings.size(); ++j) EXPECT_EQ(lists.hits[lists.splits[i] + j].prim, crossings[j].prim);
        found += want.found();
    }
    EXPECT_GT(found, n / 10);
    std::vector<Hit> short_out(n - 1);
    EXPECT_THROW(closest_hits(*accel, rows, short_out), Error);
}

// `coherent` is the closest-hit packet path's hint: every batch without one refuses it (rows,
// spans and points alike) instead of ignoring it, and closest hits take it with the same answers.
TEST(RayRows, CoherentIsRefusedByEveryBatchWithoutAPacketPath) {
    const Scene scene = torus_scene(1.0f, 0.4f, 16, 8);
    const auto accel = build_accel("bvh8", scene);
    const std::vector<float> data = {1.0f, 0.05f, 3, 0, 0, -1, 0, 100, 0.2f, 0.1f, 3, 0, 0, -1, 0, 100};  // the tube, the hole
    const RayRows rows{data.data(), 2, 8};
    std::vector<Ray> rays(2);
    for (size_t i = 0; i < 2; ++i) ASSERT_TRUE(make_ray(&data[8 * i], rays[i]));
    BatchOptions coherent;
    coherent.coherent = true;
    std::vector<Hit> hits(2);
    std::vector<uint8_t> flags(2);
    std::vector<uint32_t> counts(2);
    const std::vector<Vec3> points = {{0, 0, 2}};
    std::vector<NearestPoint> nearest(1);
    std::vector<float> d(1);
    std::vector<uint8_t> inside(1);
    const PointQueries queries(*accel, scene);
    const auto refused = [](const std::function<void()>& query, const std::string& name) {
        try {
            query();
            ADD_FAILURE() << name << " took coherent";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(name + " batch: coherent"), std::string::npos) << e.what();
        }
    };
    refused([&] { occlusions(*accel, rows, flags, coherent); }, "any-hit");
    refused([&] { accel->occluded(rays, flags, coherent); }, "any-hit");
    refused([&] { crossing_counts(*accel, rows, counts, coherent); }, "count");
    refused([&] { accel->count_hits(rays, counts, coherent); }, "count");
    refused([&] { crossing_lists(*accel, rows, coherent); }, "all-hits");
    refused([&] { accel->all_hits(rays, coherent); }, "all-hits");
    refused([&] { accel->closest_points(points, nearest, coherent); }, "closest-point");
    refused([&] { queries.closest_points(points, nearest, coherent); }, "closest points");
    refused([&] { queries.distances(points, d, coherent); }, "distances");
    refused([&] { queries.occupancy(points, inside, 1, coherent); }, "occupancy");
    refused([&] { queries.signed_distances(points, d, 1, coherent); }, "signed distances");
    EXPECT_EQ(closest_hits(*accel, rows, hits, coherent), 0u);
    for (size_t i = 0; i < 2; ++i) EXPECT_TRUE(thicket::testing::identical_hits(hits[i], accel->intersect(rays[i]))) << i;
    EXPECT_TRUE(hits[0].found());
    EXPECT_FALSE(hits[1].found());
}

}  // namespace point_queries_test
