// The queries beyond closest and any hit (all crossings, their count, the closest point) for
// every registered variant against brute force, on the nasty scenes. Brute force's own all_hits
// enumerates every root of every primitive; the structures' default asks closest hit again past
// each crossing: the two must list the same crossings. Triangle scenes only (see below).
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <sstream>

#include "support/test_scenes.h"
#include "support/variant_cover.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace thicket::testing::extra_queries_test {
namespace {

// A quarter under the sanitizers (about ten times slower), which keeps CI's sanitizer job within
// its budget; the Release job runs them all (about 25 s of CPU over every variant).
#ifdef THICKET_SANITIZED
constexpr size_t kRays = 250;
#else
constexpr size_t kRays = 1000;
#endif
constexpr size_t kPoints = kRays;

/// Brute force's crossings per ray and closest points, computed once per scene per process.
struct ExtraReference {
    std::vector<Ray> rays;
    HitLists lists;
    std::vector<Vec3> points;
    std::vector<NearestPoint> closest;  ///< empty when the scene has shapes
};

/// Brute force with the same triangle test (`isect`) as the structure checked: the two tests
/// disagree on rays through edges, which is what these scenes are full of.
const ExtraReference& reference_for(const Scene& scene, const std::string& isect) {
    static std::map<std::string, std::unique_ptr<ExtraReference>> cache;
    auto& slot = cache[scene.name + "/" + isect];
    if (slot) return *slot;
    slot = std::make_unique<ExtraReference>();
    slot->rays = conformance_rays(scene, kRays, 5);
    const std::unique_ptr<Accel> brute = build_accel("brute:isect=" + isect, scene);
    slot->lists = brute->all_hits(slot->rays);
    // Points around and on the scene: uniform in the box grown by half its size, and every ray's
    // first crossing (a point on the surface, distance about 0).
    std::mt19937 rng(9);
    const Aabb b = scene.bounds();
    if (!b.empty()) {
        const Vec3 lo = b.min - b.extent() * 0.5f, size = b.extent() * 2.0f;
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        while (slot->points.size() < kPoints / 2) slot->points.push_back(lo + size * Vec3{u(rng), u(rng), u(rng)});
        for (size_t i = 0; i < slot->rays.size() && slot->points.size() < kPoints; ++i)
            if (slot->lists.splits[i + 1] > slot->lists.splits[i]) {
                const Ray& r = slot->rays[i];
                slot->points.push_back(r.org + r.dir * slot->lists.hits[slot->lists.splits[i]].t);
            }
    }
    if (brute->has_closest_point()) {
        slot->closest.resize(slot->points.size());
        brute->closest_points(slot->points, slot->closest);
    }
    return *slot;
}

bool same_t(float got, float want) { return std::fabs(got - want) <= kSameCrossing * std::fabs(want); }

class ExtraQueries : public ::testing::TestWithParam<std::string> {};

TEST_P(ExtraQueries, CrossingsAndClosestPointsMatchBruteForce) {
    for (const Scene& scene : nasty_scenes()) {
        // Triangle scenes only, for now: on the mixed scene the fractal and implicit kernels have
        // so many roots along a ray that stepping from root to root takes minutes per variant, and
        // 3 of 1000 rays there list a crossing more than brute force (roots closer together than
        // the kernels' own tolerance). Shapes' crossings are not conformance-checked yet.
        if (scene.has_shapes()) continue;
        SCOPED_TRACE(scene.name);
        const ExtraReference& ref = reference_for(scene, parse_accel_spec(GetParam()).get("isect"));
        const std::unique_ptr<Accel> accel = build_accel(GetParam(), scene);

        BatchOptions two;  // threads, so that the batch forms' chunking is exercised
        two.threads = 2;
        const HitLists lists = accel->all_hits(ref.rays, two);
        std::vector<uint32_t> counts(ref.rays.size());
        accel->count_hits(ref.rays, counts, two);
        ASSERT_EQ(lists.splits.size(), ref.rays.size() + 1);
        size_t wrong = 0;
        std::ostringstream first;
        for (size_t i = 0; i < ref.rays.size(); ++i) {
            const size_t n = lists.splits[i + 1] - lists.splits[i], want = ref.lists.splits[i + 1] - ref.lists.splits[i];
            EXPECT_EQ(counts[i], n) << "ray " << i << ": count_hits disagrees with all_hits";
            bool ok = n == want;
            for (size_t k = 0; ok && k < n; ++k)
                ok = same_t(lists.hits[lists.splits[i] + k].t, ref.lists.hits[ref.lists.splits[i] + k].t);
            if (!ok && wrong++ == 0)
                first << "ray " << i << ": " << n << " crossings, brute force " << want;
        }
        EXPECT_EQ(wrong, 0u) << wrong << " rays list other crossings than brute force; first: " << first.str();

        if (ref.closest.empty() || !accel->has_closest_point()) {
            if (!ref.points.empty()) {
                EXPECT_THROW(accel->closest_point(ref.points[0]), Error);
            }
            continue;
        }
        std::vector<NearestPoint> got(ref.points.size());
        accel->closest_points(ref.points, got, two);
        for (size_t i = 0; i < got.size(); ++i) {
            const NearestPoint& want = ref.closest[i];
            ASSERT_EQ(got[i].found(), want.found()) << "point " << i;
            // Equally close primitives (a shared vertex) may differ; the distance may not.
            EXPECT_NEAR(got[i].distance, want.distance, 1e-5 * want.distance + 1e-30) << "point " << i;
            EXPECT_NEAR(length(got[i].point - ref.points[i]), got[i].distance, 1e-5 * got[i].distance + 1e-30)
                << "point " << i << ": the reported point is not at the reported distance";
        }
    }
}

/// The example: a closed unit cube shot through the diagonal of each face (the edge two
/// triangles share) counts 2 crossings, not 3 or 4, for every structure; and from inside, 1.
TEST_P(ExtraQueries, ClosedCubeCountsEachCrossingOnce) {
    TriangleMesh cube;
    for (int i = 0; i < 8; ++i) cube.positions.push_back({float(i >> 2 & 1), float(i >> 1 & 1), float(i & 1)});
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : quads)
        for (int k : {q[0], q[1], q[2], q[0], q[2], q[3]}) cube.indices.push_back(uint32_t(k));
    Scene scene;
    scene.name = "unit-cube";
    scene.add_mesh(cube);
    const std::unique_ptr<Accel> accel = build_accel(GetParam(), scene);
    for (float s : {0.1f, 0.25f, 0.5f, 0.75f, 0.9f}) {
        // Through the diagonal of the faces x = 0 and x = 1 (each split along it), along x, and
        // likewise for y and z; then from the centre outward.
        for (int axis = 0; axis < 3; ++axis) {
            Vec3 org{s, s, s}, dir{0, 0, 0};
            org[axis] = -1.0f;
            dir[axis] = 1.0f;
            const Ray ray{org, 0.0f, dir, kInfinity};
            EXPECT_EQ(accel->count_hits(ray), 2u) << "axis " << axis << " at " << s;
            const Ray out{{0.5f, 0.5f, 0.5f}, 0.0f, dir, kInfinity};
            EXPECT_EQ(accel->count_hits(out), 1u) << "axis " << axis << " from the centre";
        }
    }
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
    std::string name = info.param;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(Registry, ExtraQueries, ::testing::ValuesIn(conformance_variants()), test_name);

}  // namespace
}  // namespace thicket::testing::extra_queries_test
