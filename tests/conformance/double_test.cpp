// The precision=double structures: every one answers double rays exactly as double brute force
// does, on the nasty and shared scenes and on scenes moved to 1e6-1e8 offsets, where the float
// structures demonstrably lose hits. The variants are every structure with a `precision` option,
// over the covering set of its registered variants, so a new option value is run by registering it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "support/test_scenes.h"
#include "support/variant_cover.h"
#include "thicket/scene/translate.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace thicket::testing::double_test {
namespace {

/// Every registered structure with a precision option: the covering set of its variants, each
/// with precision=double (ctest's families pick them up by the structure's name).
std::vector<std::string> double_variants() {
    std::vector<std::string> out;
    for (const AccelInfo& info : accel_registry()) {
        const bool has_precision = std::any_of(info.options.begin(), info.options.end(),
                                               [](const OptionInfo& o) { return o.key == "precision"; });
        if (!has_precision) continue;
        for (const std::string& v : covering_variants(info.variants))
            out.push_back(v + (v.find(':') == std::string::npos ? ":" : ",") + "precision=double");
    }
    return out;
}

#ifdef THICKET_SANITIZED
constexpr size_t kBruteTestsPerScene = 2'000'000;
#else
constexpr size_t kBruteTestsPerScene = 8'000'000;
#endif

/// Shared scenes above this many triangles (the dragon) are left out: each variant builds its
/// tree over every scene (sbvh takes 11 s on the dragon), and the float suite covers the builders
/// there; the double code paths are the same on every scene.
constexpr size_t kLargestSharedScene = 300'000;

/// Rays that double brute force answers on `scene` for about kBruteTestsPerScene triangle tests.
size_t rays_for(const Scene& scene) {
    return std::clamp<size_t>(kBruteTestsPerScene / std::max<size_t>(1, scene.primitive_count()), 40, 1000);
}


RayD moved_ray(const Ray& r, double offset) {
    RayD d = to_double(r);
    d.org = d.org + Vec3d(offset, offset, offset);
    return d;
}

/// "" when `got` answers every ray as `want` does (closest hit, any hit, and the batch forms),
/// else the first difference.
std::string compare_double(const Accel& got, const Accel& want, const std::vector<RayD>& rays) {
    std::vector<HitD> batch(rays.size());
    std::vector<uint8_t> batch_occluded(rays.size());
    got.intersect_double(rays, batch);
    got.occluded_double(rays, batch_occluded);
    for (size_t i = 0; i < rays.size(); ++i) {
        const HitD a = got.intersect_double(rays[i]), b = want.intersect_double(rays[i]);
        // Two triangles at exactly the same t are one answer (a shared edge or vertex).
        const bool same = a.t == b.t && (a.prim == b.prim || (a.found() && b.found()));
        if (!same)
            return "ray " + std::to_string(i) + ": prim " + std::to_string(a.prim) + " at t " + std::to_string(a.t) +
                   ", double brute force: prim " + std::to_string(b.prim) + " at t " + std::to_string(b.t);
        if (got.occluded_double(rays[i]) != b.found())
            return "ray " + std::to_string(i) + ": any-hit says " + (b.found() ? "miss" : "hit");
        if (batch[i].t != a.t || batch[i].prim != a.prim || bool(batch_occluded[i]) != b.found())
            return "ray " + std::to_string(i) + ": the batch answer differs from the single-ray one";
    }
    return "";
}

/// "" when every ray aimed from outside at the centroid of a well-shaped triangle, along its
/// normal tilted a little, hits something no farther than that centroid (in double, from the
/// scene's double vertices); else the first ray that does not. Brute force and the BVH share the
/// triangle and box tests, so this is what catches a fault in those shared parts.
std::string missed_centroids(const Accel& accel, const Scene& scene) {
    std::mt19937 rng(7);
    for (size_t tri = 0; tri < scene.mesh.triangle_count(); tri += 3) {
        const Vec3d a = scene.mesh.vertex_double(tri, 0), b = scene.mesh.vertex_double(tri, 1),
                    c = scene.mesh.vertex_double(tri, 2);
        const Vec3d n = cross(b - a, c - a);
        const double size = std::sqrt(std::max(dot(b - a, b - a), dot(c - a, c - a)));
        if (!(length(n) > 0.1 * size * size)) continue;  // thin or degenerate: no well-conditioned aim
        const Vec3 jitter = random_unit_vector(rng);
        const Vec3d dir = normalize(normalize(n) + Vec3d(jitter) * 0.3);
        const Vec3d centroid = (a + b + c) * (1.0 / 3.0);
        const double distance = 4.0 * size;
        const RayD ray{centroid + dir * distance, 0.0, -dir, std::numeric_limits<double>::infinity()};
        const HitD hit = accel.intersect_double(ray);
        // The origin itself is rounded: a few ulps of the coordinates' magnitude, far from the origin.
        const double scale = std::max({std::fabs(centroid.x), std::fabs(centroid.y), std::fabs(centroid.z), 1.0});
        const double slack = distance * 1e-9 + 16 * std::numeric_limits<double>::epsilon() * scale;
        if (!hit.found() || hit.t > distance + slack)
            return "triangle " + std::to_string(tri) + ": hit " + std::to_string(hit.prim) + " at t " +
                   std::to_string(hit.t) + ", its centroid at " + std::to_string(distance);
    }
    return "";
}

class DoublePrecision : public ::testing::TestWithParam<std::string> {
protected:
    std::string reference_spec() const { return "brute:precision=double,isect=" + parse_accel_spec(GetParam()).get("isect"); }

    void check_scene(const Scene& scene, size_t count) {
        SCOPED_TRACE("scene " + scene.name);
        const auto accel = build_accel(GetParam(), scene);
        ASSERT_TRUE(accel->double_precision());
        // Brute force against itself: what can still fail is its consistency (any-hit, batches).
        const bool is_reference = accel->spec() == parse_accel_spec(reference_spec()).str();
        const auto brute = is_reference ? nullptr : build_accel(reference_spec(), scene);
        std::vector<RayD> rays;
        for (const Ray& r : conformance_rays(scene, count)) rays.push_back(to_double(r));
        EXPECT_EQ(compare_double(*accel, brute ? *brute : *accel, rays), "");
        // Float rays are widened and the hit rounded: the same answer as the double entry point.
        for (size_t i = 0; i < std::min<size_t>(rays.size(), 200); ++i) {
            const Ray r{rays[i].org.to_float(), float(rays[i].tmin), rays[i].dir.to_float(), float(rays[i].tmax)};
            const Hit f = accel->intersect(r);
            const HitD d = accel->intersect_double(to_double(r));
            ASSERT_EQ(f.prim, d.prim) << "ray " << i;
            ASSERT_EQ(f.t, float(d.t)) << "ray " << i;
        }
    }
};

TEST_P(DoublePrecision, NastyScenes) {
    for (const Scene& scene : nasty_scenes()) {
        if (scene.has_shapes()) {
            // Shapes have no double form: refused, naming the option and the scene.
            try {
                build_accel(GetParam(), scene);
                ADD_FAILURE() << "precision=double built over the shapes of " << scene.name;
            } catch (const Error& e) {
                EXPECT_NE(std::string(e.what()).find("precision=double takes triangle scenes only"), std::string::npos)
                    << e.what();
            }
            continue;
        }
        check_scene(scene, 600);
    }
}

/// The shared scenes, for every double structure but brute force: it is the reference each of them
/// is compared with there (its own consistency, any hit and batches, is checked on the nasty
/// scenes and far from the origin; on the shared scenes it cost 20 s of a Release run).
class DoublePrecisionShared : public DoublePrecision {};

TEST_P(DoublePrecisionShared, SharedScenes) {
    const auto files = shared_scene_files();
    if (files.empty()) GTEST_SKIP() << shared_scenes_missing_message();
    for (const std::string& file : files) {
        const Scene& scene = cached_scene(file);
        if (scene.primitive_count() > kLargestSharedScene) continue;
        check_scene(scene, rays_for(scene));
    }
}

/// At 1e6, 1e7 and 1e8 the double structure answers every ray as double brute force; the float
/// BVH of the same (rounded) scene, traced with the rounded rays, is printed beside it.
TEST_P(DoublePrecision, FarFromTheOrigin) {
    const Scene base = nasty_scenes().back();  // the random soup: triangles of every size
    ASSERT_FALSE(base.has_shapes());
    for (const double offset : {1e6, 1e7, 1e8}) {
        const Scene scene = translated_scene(base, offset);
        SCOPED_TRACE(scene.name);
        const auto accel = build_accel(GetParam(), scene);
        const auto brute = build_accel(reference_spec(), scene);
        const auto as_float = build_accel("bvh", scene);
        std::vector<RayD> rays;
        for (const Ray& r : conformance_rays(base, 500)) rays.push_back(moved_ray(r, offset));
        EXPECT_EQ(compare_double(*accel, *brute, rays), "");
        size_t float_differs = 0;
        for (const RayD& r : rays) {
            const HitD want = brute->intersect_double(r);
            const Ray f{r.org.to_float(), float(r.tmin), r.dir.to_float(), float(r.tmax)};
            if (as_float->intersect(f).prim != want.prim) ++float_differs;
        }
        std::printf("[ offset   ] %s at %.0e: double agrees on every one of %zu rays; float bvh differs on %zu\n",
                    accel->spec().c_str(), offset, rays.size(), float_differs);
        EXPECT_EQ(missed_centroids(*accel, scene), "") << "a judge that shares no code with the structures";
    }
}

std::string double_test_name(const ::testing::TestParamInfo<std::string>& info) {
    std::string name = info.param;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

std::vector<std::string> double_variants_but_brute() {
    std::vector<std::string> out;
    for (const std::string& v : double_variants())
        if (parse_accel_spec(v).name != "brute") out.push_back(v);
    return out;
}

INSTANTIATE_TEST_SUITE_P(Double, DoublePrecision, ::testing::ValuesIn(double_variants()), double_test_name);
INSTANTIATE_TEST_SUITE_P(Double, DoublePrecisionShared, ::testing::ValuesIn(double_variants_but_brute()),
                         double_test_name);

/// A 1 cm triangle 1e7 m from the origin, where float's spacing is 1 m: its float vertices
/// collapse, so every float structure misses the ray through its middle; the double ones hit it
/// at the distance double brute force computes from the file's coordinates.
TEST(DoublePrecisionOffset, FloatLosesTheHitDoubleFinds) {
    const double o = 1e7;
    TriangleMesh mesh;
    mesh.positions_double = {{o, o, o}, {o + 0.01, o, o}, {o, o + 0.01, o}};
    for (const Vec3d& p : mesh.positions_double) mesh.positions.push_back(p.to_float());
    mesh.indices = {0, 1, 2};
    Scene scene;
    scene.name = "centimetre triangle at 1e7";
    scene.add_mesh(mesh);
    const RayD ray{{o + 0.002, o + 0.003, o - 5.0}, 0.0, {0, 0, 1}, std::numeric_limits<double>::infinity()};
    const Ray rounded{ray.org.to_float(), 0.0f, ray.dir.to_float(), kInfinity};
    for (const char* spec : {"brute", "bvh", "bvh8"}) EXPECT_FALSE(build_accel(spec, scene)->intersect(rounded).found()) << spec;
    for (const char* spec : {"brute:precision=double", "bvh:precision=double", "bvh:precision=double,isect=watertight"}) {
        const HitD hit = build_accel(spec, scene)->intersect_double(ray);
        EXPECT_EQ(hit.prim, 0u) << spec;
        EXPECT_NEAR(hit.t, 5.0, 1e-6) << spec;
        EXPECT_NEAR(hit.u, 0.2, 1e-6) << spec;
        EXPECT_NEAR(hit.v, 0.3, 1e-6) << spec;
    }
    // A float structure refuses double rays, naming the option that builds one that takes them.
    try {
        build_accel("bvh", scene)->intersect_double(ray);
        ADD_FAILURE() << "a float bvh answered a double ray";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("precision=double"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace thicket::testing::double_test
