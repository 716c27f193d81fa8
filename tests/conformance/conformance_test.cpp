// The conformance suite: every registered structure variant, on generated nasty scenes and on
// the shared real scenes, must answer exactly like brute force. A new structure is tested by
// registering it; nothing here names a structure.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "support/double_reference.h"
#include "support/reference.h"
#include "support/variant_cover.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"

namespace thicket::testing::conformance_test {
namespace {

#ifdef THICKET_SANITIZED
constexpr size_t kRealSceneBudget = 25'000'000;
#else
constexpr size_t kRealSceneBudget = 100'000'000;
#endif

/// Rays per real scene that brute force answers: it costs rays x primitives, so about
/// kRealSceneBudget tests per scene (a quarter of that under the sanitizers, ten times slower).
size_t shared_scene_brute_rays(const Scene& scene) {
    return std::clamp<size_t>(kRealSceneBudget / std::max<size_t>(1, scene.primitive_count()), 200, 4000);
}

/// Rays per real scene in all: in Release 10^4 (the dragon's 200 brute-force rays alone prove
/// little), the `bvh` answering those brute force does not after agreeing with it on all it does
/// (reference_for), and brute force judging any ray on which a structure and the `bvh` differ.
/// Sanitized builds keep to brute force's rays.
#ifdef THICKET_SANITIZED
constexpr size_t kSharedSceneRays = 0;
#else
constexpr size_t kSharedSceneRays = 10'000;
#endif
size_t shared_scene_rays(const Scene& scene) { return std::max(kSharedSceneRays, shared_scene_brute_rays(scene)); }

constexpr size_t kNastySceneRays = 3000;

/// Sanitized builds run about ten times slower: there the real scenes above kSanitizerScenePrims
/// (the dragon) are left to the Release job, whose code paths they share, unless THICKET_FULL is
/// set (`scripts/test --full`). Every nasty scene runs everywhere.
constexpr size_t kSanitizerScenePrims = 100'000;
bool in_sanitizer_scope(const Scene& scene) {
#ifdef THICKET_SANITIZED
    const char* full = std::getenv("THICKET_FULL");
    return (full && *full && std::string(full) != "0") || scene.primitive_count() <= kSanitizerScenePrims;
#else
    (void)scene;
    return true;
#endif
}

/// Every reference the suite reads, for both triangle tests: what the ctest fixture
/// conformance.references computes once for all families (see reference_for).
TEST(References, Precompute) {
    const char* dir = std::getenv("THICKET_REFERENCE_CACHE");
    if (dir) {
        // Answers left by an earlier run may come from an older brute force: start empty.
        std::filesystem::remove_all(dir);
        std::filesystem::create_directories(dir);
    }
    for (const char* isect : {"moller", "watertight"}) {
        for (const Scene& scene : nasty_scenes())
            EXPECT_EQ(reference_for("nasty:" + scene.name, scene, isect, kNastySceneRays).hits.size(), kNastySceneRays);
        for (const std::string& file : shared_scene_files()) {
            const Scene& scene = cached_scene(file);
            if (!in_sanitizer_scope(scene)) continue;
            EXPECT_EQ(reference_for(file, scene, isect, shared_scene_rays(scene), shared_scene_brute_rays(scene)).hits.size(),
                      shared_scene_rays(scene));
        }
    }
    if (dir) {
        EXPECT_FALSE(std::filesystem::is_empty(dir)) << "no reference was written to " << dir;
    }
}

#ifdef THICKET_CONFORMANCE_FAMILIES
/// "A new structure is tested by registering it": ctest runs one conformance entry per family
/// listed in tests/CMakeLists.txt, so that list must name every registered structure.
TEST(References, EveryRegisteredStructureHasACtestFamily) {
    const std::string listed = std::string(",") + THICKET_CONFORMANCE_FAMILIES + ",";
    for (const AccelInfo& info : accel_registry())
        EXPECT_NE(listed.find("," + info.name + ","), std::string::npos)
            << "'" << info.name << "' is registered but tests/CMakeLists.txt runs no conformance family for it";
}
#endif

class Conformance : public ::testing::TestWithParam<std::string> {
protected:
    std::string isect() const { return parse_accel_spec(GetParam()).get("isect"); }

    void check_scene(const Scene& scene, const std::string& key, size_t rays, size_t brute_rays = SIZE_MAX) {
        SCOPED_TRACE("scene " + scene.name);
        const Reference& ref = reference_for(key, scene, isect(), rays, brute_rays);
        std::unique_ptr<Accel> accel = build_accel(GetParam(), scene);
        const AccelStats stats = accel->stats();
        for (const auto& [key, value] : stats.extra)
            if (key == kLimitedKey)
                std::printf("[ limited  ] %s, %s: %s\n", scene.name.c_str(), accel->spec().c_str(), value.c_str());
        const std::string mismatch = compare_with_reference(*accel, ref, scene.name);
        EXPECT_EQ(mismatch, "");
        check_bounds(*accel, scene);
        check_filter(scene, ref);
    }

    /// Brute force against the independent double-precision reference (no filter): every
    /// difference must be an ill-conditioned hit, the filter's rejections included.
    void check_filter(const Scene& scene, const Reference& ref) const {
        if (scene.has_shapes() || parse_accel_spec(GetParam()).name != "brute") return;
        // On brute force's own rays only (the double-precision reference costs as much as it does).
        std::vector<Ray> rays;
        std::vector<Hit> hits;
        for (size_t i = 0; i < ref.rays.size(); i += ref.brute_stride) {
            rays.push_back(ref.rays[i]);
            hits.push_back(ref.hits[i]);
        }
        const FilterCheck c = check_against_double_reference(scene, isect(), rays, hits);
        std::printf("[ filter   ] %s (%s): %zu rays, %zu agree with double precision, %zu differ on "
                    "ill-conditioned hits (%zu of them dropped by the filter), %zu unexplained\n",
                    scene.name.c_str(), isect().c_str(), c.rays, c.agree, c.ill_conditioned, c.filter_rejections,
                    c.unexplained);
        EXPECT_EQ(c.unexplained, 0u) << "first: " << c.first_unexplained;
    }

    static void check_bounds(const Accel& accel, const Scene& scene) {
        const Aabb want = scene.bounds();
        const Aabb got = accel.bounds();
        if (want.empty()) {
            EXPECT_TRUE(got.empty()) << "bounds of an empty scene must be empty";
            return;
        }
        for (int a = 0; a < 3; ++a) {
            EXPECT_LE(got.min[a], want.min[a]) << "bounds must contain every primitive (axis " << a << ")";
            EXPECT_GE(got.max[a], want.max[a]) << "bounds must contain every primitive (axis " << a << ")";
        }
    }
};

TEST_P(Conformance, NastyScenes) {
    for (const Scene& scene : nasty_scenes()) check_scene(scene, "nasty:" + scene.name, kNastySceneRays);
}

/// The shared real scenes, under shared_scene_variants() (every option value of every structure).
class SharedSceneConformance : public Conformance {};

TEST_P(SharedSceneConformance, SharedScenes) {
    const auto files = shared_scene_files();
    if (files.empty()) GTEST_SKIP() << shared_scenes_missing_message();
    const bool is_reference = parse_accel_spec(GetParam()).name == "brute";
    for (const std::string& file : files) {
        const Scene& scene = cached_scene(file);
        if (!in_sanitizer_scope(scene)) {
            std::printf("[ scope    ] %s: %zu primitives: left to the Release job in a sanitized build "
                        "(THICKET_FULL=1 runs it here too)\n",
                        file.c_str(), scene.primitive_count());
            continue;
        }
        if (is_reference) {
            // Brute force checked against itself proves nothing; what can still fail is its own
            // consistency: any-hit must say "hit" exactly when the closest hit exists.
            SCOPED_TRACE("scene " + scene.name);
            const Reference& ref =
                reference_for(file, scene, isect(), shared_scene_rays(scene), shared_scene_brute_rays(scene));
            for (size_t i = 0; i < ref.rays.size(); ++i)
                ASSERT_EQ(bool(ref.occluded[i]), ref.hits[i].found()) << "ray " << i;
            // Every answer of the reference, whoever gave it, names a triangle that double
            // precision confirms at that t: a judge that does not share the structures' code.
            const FilterCheck named = check_named_primitives(scene, ref.rays, ref.hits);
            std::printf("[ named    ] %s (%s): %zu hits, %zu confirmed in double precision, %zu ill-conditioned, "
                        "%zu wrong\n",
                        scene.name.c_str(), isect().c_str(), named.rays, named.agree, named.ill_conditioned,
                        named.unexplained);
            EXPECT_EQ(named.unexplained, 0u) << "first: " << named.first_unexplained;
            EXPECT_GT(named.agree, named.rays * 9 / 10) << "most hits are well-conditioned";
#ifndef THICKET_SANITIZED  // as costly as brute force itself: the Release job's
            if (isect() == "moller") check_filter(scene, ref);
#endif
            continue;
        }
        check_scene(scene, file, shared_scene_rays(scene), shared_scene_brute_rays(scene));
    }
}

TEST_P(Conformance, StatisticsAreConsistent) {
    for (const Scene& scene : nasty_scenes()) {
        SCOPED_TRACE("scene " + scene.name);
        const auto start = std::chrono::steady_clock::now();
        auto accel = build_accel(GetParam(), scene);
        const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        const AccelStats s = accel->stats();
        EXPECT_EQ(s.spec, accel->spec());
        EXPECT_EQ(s.primitives, scene.primitive_count());
        // The build time is part of the wall time around build_accel (a figure in other units, or
        // one never set from a clock, lands outside).
        EXPECT_GE(s.build_ms, 0.0);
        EXPECT_LE(s.build_ms, wall_ms);
        EXPECT_LE(s.leaves, s.nodes);
        EXPECT_GE(s.sah_cost, 0.0);
        if (scene.primitive_count() > 0 && s.sah_cost == 0.0) {
            // 0 means "undefined" (AccelStats): a structure that leaves the common SAH column
            // empty must say why, under the one key meant for it (not any figure naming the SAH).
            EXPECT_TRUE(sah_cost_explained(s)) << "no SAH cost, and no '" << kSahUndefinedKey
                                               << "' figure that says why";
        }
        // Counting is free of side effects: counting twice gives the same figures.
        const Ray ray{scene.bounds().center() - Vec3(0, 0, 10), 0.0f, {0, 0, 1}, kInfinity};
        RayCounters a, b;
        accel->intersect(ray, a);
        accel->intersect(ray, b);
        EXPECT_EQ(a.nodes, b.nodes);
        EXPECT_EQ(a.prims, b.prims);
        EXPECT_LE(a.prims, most_tests_per_query(*accel, scene.primitive_count()))
            << "no primitive may be tested twice by one query (spatial-split BVHs: once per reference)";
    }
}

TEST_P(Conformance, SaveLoadRoundTrip) {
    const Scene scene = nasty_scenes().back();  // the random soup
    auto accel = build_accel(GetParam(), scene);
    const auto path = std::filesystem::temp_directory_path() /
                      ("thicket-conformance-" + std::to_string(::getpid()) + "-" +
                       std::to_string(std::hash<std::string>{}(GetParam())) + ".accel");
    try {
        save_accel(*accel, scene, path.string());
    } catch (const Error& e) {
        // A structure may not support saving; then it must say so, and leave no file behind.
        EXPECT_NE(std::string(e.what()).find("cannot be saved"), std::string::npos) << e.what();
        EXPECT_FALSE(std::filesystem::exists(path));
        return;
    }
    auto loaded = load_accel(path.string(), scene);
    std::filesystem::remove(path);
    EXPECT_EQ(loaded->spec(), accel->spec());
    const Reference& ref = reference_for("nasty:" + scene.name, scene, isect(), kNastySceneRays);
    EXPECT_EQ(compare_with_reference(*loaded, ref, scene.name), "");
    for (const Ray& r : ref.rays) {
        const Hit a = accel->intersect(r), b = loaded->intersect(r);
        ASSERT_EQ(a.prim, b.prim);
        ASSERT_EQ(a.t, b.t);
    }
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
    std::string name = info.param;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(Registry, Conformance, ::testing::ValuesIn(conformance_variants()), test_name);
INSTANTIATE_TEST_SUITE_P(Registry, SharedSceneConformance, ::testing::ValuesIn(shared_scene_variants()), test_name);

}  // namespace
}  // namespace thicket::testing::conformance_test
