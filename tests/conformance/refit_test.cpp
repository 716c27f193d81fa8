// Refit (Accel::refit after Scene::set_vertices) against brute force on the moved scene: every
// refittable structure (bvh, bvh8 under every ISA this CPU runs, spatial splits included, obb)
// is built on a scene, the scene's vertices are moved (bent, exploded, moved and scaled far
// away), the structure is refitted, and its closest hits and occlusion must follow the
// conformance suite's agreement rule against brute force on the moved scene, and equal a
// rebuild's; scans and CAD meshes, whose degenerate triangles cross the degenerate test under
// rigid, affine and mirrored motions, refit as well. Then the refusals: wrong vertex counts,
// non-refittable structures, a topology change.
#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "support/reference.h"
#include "support/test_scenes.h"
#include "support/variant_cover.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh8/bvh8.h"
#include "thicket/bvh8/isa.h"
#include "thicket/core/error.h"

namespace thicket::testing::refit_test {
namespace {

#ifdef THICKET_SANITIZED
constexpr size_t kRays = 300;
#else
constexpr size_t kRays = 1500;
#endif

/// A closed UV sphere of radius 1 at the origin beside a wavy sheet: shared vertices (so moving
/// one moves several triangles), both curved and flat parts. One geometry.
Scene generated_scene() {
    TriangleMesh m;
    const int rings = 24, segments = 48;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const float theta = float(M_PI) * float(r) / float(rings);
            const float phi = 2.0f * float(M_PI) * float(s) / float(segments);
            m.positions.push_back({std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
        }
    auto at = [&](int r, int s) { return uint32_t(r * segments + (s % segments)); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            // The poles' rows collapse to a point: only the non-degenerate half of those quads.
            if (r != 0) m.indices.insert(m.indices.end(), {at(r, s), at(r + 1, s), at(r, s + 1)});
            if (r != rings - 1) m.indices.insert(m.indices.end(), {at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
        }
    const auto base = uint32_t(m.positions.size());
    const int n = 30;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const float x = 1.5f + 3.0f * float(i) / n, z = -1.5f + 3.0f * float(j) / n;
            m.positions.push_back({x, 0.2f * std::sin(3.0f * x) * std::cos(2.0f * z), z});
        }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const uint32_t a = base + uint32_t(i * (n + 1) + j), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
        }
    Scene scene;
    scene.name = "sphere-and-sheet";
    scene.add_mesh(m);
    return scene;
}

/// What a scan or a CAD export holds beside its surface: a height field far from the origin
/// (coordinates near 100, cells of 0.05), with fill triangles whose three vertices lie on one
/// grid line (exactly collinear at the build: an affine map's rounding gives them an interior)
/// and slivers just past the degenerate test (sine 1.9e-6 at the build: the scale 0.3 across
/// them and the rounding of the move take some of them below it), unless `slivers` is false.
Scene scan_like_scene(bool slivers) {
    TriangleMesh m;
    const int n = 40;
    const Vec3 corner(100.0f, 50.0f, 20.0f);
    const float cell = 0.05f;
    auto height = [](int i, int j) { return 0.1f * std::sin(0.3f * float(i)) * std::cos(0.2f * float(j)); };
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
            m.positions.push_back(corner + Vec3(float(i) * cell, float(j) * cell, height(i, j)));
    auto at = [&](int i, int j) { return uint32_t(i * (n + 1) + j); };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1),
                                               at(i, j + 1)});
    for (int i = 0; i + 2 <= n; i += 2)
        for (int j = 0; j <= n; j += 4) {
            // Three vertices of one grid row, in a straight line along x at the same height.
            const uint32_t b = uint32_t(m.positions.size());
            for (int k = 0; k < 3; ++k) m.positions.push_back(corner + Vec3(float(i + k) * cell, float(j) * cell, 0.3f));
            m.indices.insert(m.indices.end(), {b, b + 1, b + 2});
        }
    // Slivers across the whole field along x (length 2), each tip one float step off the line
    // in y (sine 1.9e-6 at the build): after the move, rounding of coordinates near 100 leaves
    // some of them below the test.
    for (int j = 0; j <= n && slivers; ++j)
        for (int k = 0; k < 8; ++k) {
            const uint32_t s = uint32_t(m.positions.size());
            const Vec3 a = corner + Vec3(0.0f, float(j) * cell + 0.01f, 0.35f + 0.02f * float(k));
            m.positions.push_back(a);
            m.positions.push_back(a + Vec3(1.0f, 0.0f, 0.0f));
            m.positions.push_back(Vec3(a.x + 2.0f, std::nextafter(a.y, 1e30f), a.z));
            m.indices.insert(m.indices.end(), {s, s + 1, s + 2});
        }
    Scene scene;
    scene.name = "scan-like";
    scene.add_mesh(m);
    return scene;
}

/// Whether triangle t of `scene` is degenerate (Triangles::degenerate).
bool degenerate_triangle(const Scene& scene, uint32_t t) {
    return Triangles<>::degenerate({scene.mesh.vertex(t, 0), scene.mesh.vertex(t, 1), scene.mesh.vertex(t, 2)});
}

/// How vertices move: each a function of the vertex and its index.
enum class Motion { Bend, Explode, FarAndLarge, Grow, Rigid, Affine, Mirror };
const char* motion_name(Motion m) {
    switch (m) {
    case Motion::Bend: return "bend";
    case Motion::Explode: return "explode";
    case Motion::FarAndLarge: return "far-and-large";
    case Motion::Grow: return "grow";
    case Motion::Rigid: return "rigid";
    case Motion::Affine: return "affine";
    case Motion::Mirror: return "mirror";
    }
    return "?";
}

/// Row-major 3x3 matrices of the linear motions: a turn of 0.7 rad about z then 0.4 rad about x
/// (no axis stays axis-parallel, so float rounding moves every vertex off its old lines), that
/// turn after the scale (1.7, 0.3, 2.3) (the user's "rotation with a non-uniform scale"), and
/// the turn after a mirror in x.
std::array<double, 9> motion_matrix(Motion motion) {
    const double cz = std::cos(0.7), sz = std::sin(0.7), cx = std::cos(0.4), sx = std::sin(0.4);
    // Rx * Rz
    const std::array<double, 9> turn = {cz, -sz, 0.0, cx * sz, cx * cz, -sx, sx * sz, sx * cz, cx};
    const std::array<double, 3> scale = motion == Motion::Affine   ? std::array<double, 3>{1.7, 0.3, 2.3}
                                        : motion == Motion::Mirror ? std::array<double, 3>{-1.0, 1.0, 1.0}
                                                                   : std::array<double, 3>{1.0, 1.0, 1.0};
    std::array<double, 9> m{};
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) m[size_t(r * 3 + k)] = turn[size_t(r * 3 + k)] * scale[size_t(k)];
    return m;
}

/// `positions` moved by `motion` within a scene of bounds `box`.
std::vector<Vec3> moved(const std::vector<Vec3>& positions, const Aabb& box, Motion motion) {
    const Vec3 c = box.center();
    const float size = max_component(box.extent());
    const std::array<double, 9> m = motion_matrix(motion);
    const Vec3 shift = Vec3(0.37f, -0.21f, 0.13f) * size;
    std::vector<Vec3> out(positions.size());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (size_t i = 0; i < positions.size(); ++i) {
        const Vec3 p = positions[i] - c;
        switch (motion) {
        case Motion::Bend: {
            // Around the y axis by an angle growing along x: the far end turns most.
            const float angle = 1.2f * p.x / size;
            out[i] = c + Vec3(p.x * std::cos(angle) - p.z * std::sin(angle), p.y + 0.3f * p.x * p.x / size,
                              p.x * std::sin(angle) + p.z * std::cos(angle));
            break;
        }
        case Motion::Explode:
            // Outward by half the scene and a random jitter of a tenth: triangles stretch, boxes
            // overlap, the worst case for a kept topology.
            out[i] = c + p * 1.5f + Vec3(unit(rng), unit(rng), unit(rng)) * (0.1f * size);
            break;
        case Motion::FarAndLarge:
            out[i] = Vec3(1.0e4f, -3.0e3f, 7.0e2f) + p * 40.0f;
            break;
        case Motion::Grow:
            // A thousand times larger where it stands: rays now start far inside planes the
            // build's bounds never reached (bvh8's FMA slab test must see the new plane bounds).
            out[i] = c + p * 1000.0f;
            break;
        case Motion::Rigid:
        case Motion::Affine:
        case Motion::Mirror: {
            // In double, rounded once to float: what a user's numpy transform gives.
            const double x = positions[i].x, y = positions[i].y, z = positions[i].z;
            out[i] = Vec3(float(m[0] * x + m[1] * y + m[2] * z), float(m[3] * x + m[4] * y + m[5] * z),
                          float(m[6] * x + m[7] * y + m[8] * z)) +
                     shift;
            break;
        }
        }
    }
    return out;
}

/// `scene` with every mesh geometry's vertices moved.
Scene moved_scene(const Scene& scene, Motion motion) {
    Scene s = scene;
    for (uint32_t id = 0; id < s.geometry_count(); ++id) {
        const Geometry g = s.geometry(id);
        if (g.vertex_count == 0) continue;
        const std::vector<Vec3> old(s.mesh.positions.begin() + g.vertex_first,
                                    s.mesh.positions.begin() + g.vertex_first + g.vertex_count);
        s.set_vertices(id, moved(old, scene.bounds(), motion));
    }
    s.name = scene.name + "+" + motion_name(motion);
    return s;
}

std::string isect_of(const std::string& spec) {
    return spec.find("isect=watertight") != std::string::npos ? "watertight" : "moller";
}

/// Every refittable variant: bvh's builders (spatial splits included), bvh8 under each ISA of this
/// CPU with both triangle tests, at quality=high (spatial splits) and compressed, the OBB tree;
/// reduced to the set that covers each option value once.
std::vector<std::string> refit_specs() {
    std::vector<std::string> specs = {"bvh",
                                      "bvh:builder=sbvh",
                                      "bvh:builder=lbvh,optimize=reinsertion,traversal=ordered-centroid",
                                      "bvh:traversal=ordered-axis,isect=watertight",
                                      "bvh8:quality=high",
                                      "bvh8:builder=lbvh",
                                      "bvh8:nodes=compressed",
                                      "bvh8:quality=high,nodes=compressed",
                                      "obb",
                                      "obb:fit=axes,isect=watertight"};
    for (Isa isa : cpu_isas()) {
        specs.push_back(std::string("bvh8:isa=") + isa_name(isa));
        specs.push_back(std::string("bvh8:isa=") + isa_name(isa) + ",isect=watertight");
    }
    // Every option value once (variant_cover.h): refit itself is one code path per structure, and
    // the traversal's cross products (each ISA with each triangle test) are conformance.bvh8's.
    return covering_variants(specs);
}

/// A gtest name that no conformance family's filter (*/NAME, */NAME_*) picks up.
std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
    std::string name = "refit_";
    for (char ch : info.param) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return name;
}

class Refit : public ::testing::TestWithParam<std::string> {};

/// Builds `spec` on `base`, moves it by `motion`, refits and checks it against brute force on
/// the moved scene and against a rebuild there.
void check_motion(const std::string& spec, const Scene& base, Motion motion, const std::string& key) {
    SCOPED_TRACE(spec + " on " + base.name + ", " + motion_name(motion));
    const Scene scene = moved_scene(base, motion);
    const std::unique_ptr<Accel> accel = build_accel(spec, base);
    ASSERT_TRUE(accel->refittable());
    accel->refit(scene);
    const Reference& ref = reference_for("refit:" + key + ":" + motion_name(motion), scene, isect_of(spec), kRays);
    EXPECT_EQ(compare_with_reference(*accel, ref, scene.name), "");

    const std::unique_ptr<Accel> rebuilt = build_accel(spec, scene);
    size_t differ = 0;
    for (const Ray& r : ref.rays) {
        const Hit a = accel->intersect(r), b = rebuilt->intersect(r);
        if (!same_closest_hit(a, b, r, *ref.probe) || accel->occluded(r) != rebuilt->occluded(r)) ++differ;
    }
    EXPECT_EQ(differ, 0u) << "rays the refitted structure answers unlike a rebuild";

    // The bounds follow the move.
    const Aabb want = scene.bounds(), got = accel->bounds();
    for (int a = 0; a < 3; ++a) {
        EXPECT_LE(got.min[a], want.min[a]);
        EXPECT_GE(got.max[a], want.max[a]);
    }
    if (accel->has_closest_point()) {
        const std::unique_ptr<Accel> brute = build_accel("brute", scene);
        std::mt19937 rng(3);
        size_t wrong = 0;
        for (int k = 0; k < 200; ++k) {
            const float radius = 0.6f * max_component(scene.bounds().extent());
            const Vec3 p = scene.bounds().center() + random_unit_vector(rng) * radius;
            if (accel->closest_point(p).distance != brute->closest_point(p).distance) ++wrong;
        }
        EXPECT_EQ(wrong, 0u) << "closest points that differ from brute force's after refit";
    }
}

TEST_P(Refit, MovedGeneratedMeshMatchesBruteForce) {
    const Scene base = generated_scene();
    for (Motion m : {Motion::Bend, Motion::Explode, Motion::FarAndLarge, Motion::Grow})
        check_motion(GetParam(), base, m, "generated");
}

/// Whether the bunny's spatial-split variants run here: in a sanitized build their four builds
/// over 69k triangles took 60-75 s each at -O1 (half the sanitizer job's refit time), for code
/// that the generated and mixed scenes already run there; the Release job runs them, and so does
/// THICKET_FULL=1 (`scripts/test --full`).
bool bunny_in_sanitizer_scope(const std::string& spec) {
#ifdef THICKET_SANITIZED
    const char* full = std::getenv("THICKET_FULL");
    const bool spatial = spec.find("sbvh") != std::string::npos || spec.find("quality=high") != std::string::npos;
    return !spatial || (full && *full && std::string(full) != "0");
#else
    (void)spec;
    return true;
#endif
}

TEST_P(Refit, BentAndExplodedBunnyMatchesBruteForce) {
    if (shared_scene_dir().empty()) GTEST_SKIP() << shared_scenes_missing_message();
    if (!bunny_in_sanitizer_scope(GetParam())) {
        std::printf("[ scope    ] %s on the bunny: spatial splits left to the Release job in a sanitized build "
                    "(THICKET_FULL=1 runs it here too)\n",
                    GetParam().c_str());
        return;
    }
    const Scene& bunny = cached_scene(shared_scene_dir() + "/bunny.ply");
    for (Motion m : {Motion::Bend, Motion::Explode}) check_motion(GetParam(), bunny, m, "bunny");
}

/// Moving there and back again gives the original structure's answers bit for bit, and an
/// unmoved refit keeps the build's SAH cost (spatial splits aside: their leaves' boxes grow to
/// whole triangles).
TEST_P(Refit, RoundTripRestoresTheBuild) {
    const Scene base = generated_scene();
    const std::unique_ptr<Accel> built = build_accel(GetParam(), base), refitted = build_accel(GetParam(), base);
    const double sah = refitted->stats().sah_cost;
    refitted->refit(base);
    const bool spatial =
        GetParam().find("sbvh") != std::string::npos || GetParam().find("quality=high") != std::string::npos;
    if (!spatial) {
        EXPECT_NEAR(refitted->stats().sah_cost, sah, 1e-9 * sah);
    }
    refitted->refit(moved_scene(base, Motion::Explode));
    refitted->refit(base);
    const std::vector<Ray> rays = conformance_rays(base, kRays, 5);
    size_t differ = 0;
    for (const Ray& r : rays) {
        const Hit a = built->intersect(r), b = refitted->intersect(r);
        if (a.t != b.t || (a.prim == kNoPrim) != (b.prim == kNoPrim) || built->occluded(r) != refitted->occluded(r))
            ++differ;
    }
    EXPECT_EQ(differ, 0u);
}

/// A scene whose triangles share ids with shapes (bvh8's callback leaves, the mixed primitive set).
TEST_P(Refit, TrianglesAmongShapesMove) {
    const Scene base = mixed_scene();
    ASSERT_GT(base.mesh.triangle_count(), 0u);
    check_motion(GetParam(), base, Motion::Bend, "mixed");
}

/// A scan's degenerate triangles cross the degenerate test both ways under an affine map (and
/// under rigid and mirrored ones as rounding falls): the refit takes every move (bvh8 keeps such
/// triangles in its blocks, its kernels reject their hits) and answers as brute force does.
TEST_P(Refit, ScanLikeMeshUnderRigidAffineAndMirroredMotions) {
    // The obb tree leaves the slivers out: a sliver just past the degenerate test is a few float
    // steps wide, Moller's u, v on it are noise (a few percent), and brute force accepts such a
    // hit anywhere in the sliver's axis-aligned box, which a diagonal sliver's oriented box does
    // not cover (2 of 1,500 rays after the mirror move, on a fresh obb build as on a refitted one).
    const bool slivers = GetParam().rfind("obb", 0) != 0;
    const Scene base = scan_like_scene(slivers);
    const Scene affine = moved_scene(base, Motion::Affine);
    size_t gained = 0, lost = 0;
    for (uint32_t t = 0; t < base.mesh.triangle_count(); ++t) {
        gained += degenerate_triangle(base, t) && !degenerate_triangle(affine, t);
        lost += !degenerate_triangle(base, t) && degenerate_triangle(affine, t);
    }
    std::printf("[ scan     ] affine move: %zu triangles gained an interior, %zu lost theirs\n", gained, lost);
    ASSERT_GT(gained, 10u) << "collinear triangles must gain an interior for this to test anything";
    if (slivers) {
        ASSERT_GT(lost, 5u) << "slivers must lose theirs";
    }
    // The reference cache's key names the scene: with and without its slivers.
    for (Motion m : {Motion::Rigid, Motion::Affine, Motion::Mirror})
        check_motion(GetParam(), base, m, slivers ? "scan-like" : "scan-like-without-slivers");
}

/// Sibenik (a CAD export, 10 degenerate triangles) under the same motions: before bvh8 kept
/// degenerate triangles in its blocks, its rigid move was refused (triangle 27301 gained an
/// interior) and its affine one too (triangle 2900 lost its own).
TEST_P(Refit, SibenikUnderRigidAffineAndMirroredMotions) {
    if (shared_scene_dir().empty()) GTEST_SKIP() << shared_scenes_missing_message();
    if (!bunny_in_sanitizer_scope(GetParam())) {
        std::printf("[ scope    ] %s on sibenik: spatial splits left to the Release job in a sanitized build "
                    "(THICKET_FULL=1 runs it here too)\n",
                    GetParam().c_str());
        return;
    }
    const Scene& sibenik = cached_scene(shared_scene_dir() + "/sibenik.ply");
    for (Motion m : {Motion::Rigid, Motion::Affine, Motion::Mirror}) check_motion(GetParam(), sibenik, m, "sibenik");
}

INSTANTIATE_TEST_SUITE_P(Structures, Refit, ::testing::ValuesIn(refit_specs()), test_name);

TEST(RefitRefusals, WrongVertexCountShapesAndNonFiniteAreRefused) {
    Scene scene = generated_scene();
    const Scene before = scene;
    const uint32_t n = scene.geometry(0).vertex_count;
    std::vector<Vec3> v(n + 1, Vec3(0.0f));
    try {
        scene.set_vertices(0, v);
        FAIL() << "a wrong vertex count was accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(std::to_string(n + 1) + " vertices given"), std::string::npos) << what;
        EXPECT_NE(what.find("has " + std::to_string(n)), std::string::npos) << what;
        EXPECT_NE(what.find("geometry 0"), std::string::npos) << what;
    }
    v.resize(n);
    v[5] = Vec3(0.0f, std::nanf(""), 0.0f);
    EXPECT_THROW(scene.set_vertices(0, v), Error);
    EXPECT_THROW(scene.set_vertices(1, v), Error) << "geometry 1 does not exist";
    EXPECT_EQ(scene.mesh.positions, before.mesh.positions) << "a refused move changed the scene";

    const uint32_t shapes = scene.add_shape(Sphere{{10, 0, 0}, 1.0f});
    try {
        scene.set_vertices(shapes, std::vector<Vec3>(3, Vec3(0.0f)));
        FAIL() << "a shape geometry accepted vertices";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no vertices"), std::string::npos) << e.what();
    }

    // A second mesh geometry moves alone.
    TriangleMesh tri;
    tri.positions = {{0, 5, 0}, {1, 5, 0}, {0, 6, 0}};
    tri.indices = {0, 1, 2};
    const uint32_t g = scene.add_mesh(tri);
    scene.set_vertices(g, std::vector<Vec3>{{0, 7, 0}, {1, 7, 0}, {0, 8, 0}});
    EXPECT_EQ(scene.mesh.vertex(scene.mesh.triangle_count() - 1, 2), Vec3(0, 8, 0));
    EXPECT_EQ(scene.mesh.vertex(0, 0), before.mesh.vertex(0, 0));
}

TEST(RefitRefusals, AnotherTopologyIsRefusedAndLeavesTheStructure) {
    const Scene base = generated_scene();
    Scene bigger = base;
    TriangleMesh tri;
    tri.positions = {{0, 5, 0}, {1, 5, 0}, {0, 6, 0}};
    tri.indices = {0, 1, 2};
    bigger.add_mesh(tri);
    const std::vector<Ray> rays = conformance_rays(base, 200, 9);
    for (const std::string spec : {"bvh", "bvh8", "obb"}) {
        const std::unique_ptr<Accel> accel = build_accel(spec, base), brute = build_accel("brute", base);
        try {
            accel->refit(bigger);
            FAIL() << spec << " refitted to a scene with another primitive count";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("rebuild"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(spec + " refit"), std::string::npos) << e.what();
        }
        for (const Ray& r : rays) EXPECT_EQ(accel->intersect(r).t, brute->intersect(r).t) << spec;
    }
}

/// A triangle flattened to a segment by the move, and back: every refittable structure takes
/// both moves (bvh8 keeps the lane, its kernels reject a degenerate lane's hits) and answers as
/// brute force does on each scene.
TEST(RefitDegenerate, ATriangleLosingAndRegainingItsInteriorIsRefitted) {
    const Scene base = generated_scene();
    Scene flat = base;
    std::vector<Vec3> v = flat.mesh.positions;
    const uint32_t a = flat.mesh.indices[30], b = flat.mesh.indices[31], c = flat.mesh.indices[32];
    v[c] = v[a] + (v[b] - v[a]) * 0.25f;  // on the segment ab: no interior left
    flat.set_vertices(0, v);
    ASSERT_TRUE(degenerate_triangle(flat, 10));
    // Straight through triangle 10 of the base scene, which brute force finds there.
    const Vec3 inside = (base.mesh.vertex(10, 0) + base.mesh.vertex(10, 1) + base.mesh.vertex(10, 2)) / 3.0f;
    const Vec3 normal = normalize(
        cross(base.mesh.vertex(10, 1) - base.mesh.vertex(10, 0), base.mesh.vertex(10, 2) - base.mesh.vertex(10, 0)));
    const Ray through{inside + normal * 0.01f, 0.0f, -normal, kInfinity};
    ASSERT_EQ(build_accel("brute", base)->intersect(through).prim, 10u);
    std::vector<std::string> specs = {"bvh", "obb", "bvh8:quality=high", "bvh8:nodes=compressed"};
    for (Isa isa : cpu_isas()) {
        specs.push_back(std::string("bvh8:isa=") + isa_name(isa));
        specs.push_back(std::string("bvh8:isa=") + isa_name(isa) + ",isect=watertight");
    }
    auto differ = [](const Accel& accel, const Accel& want, const Scene& scene) {
        size_t n = 0;
        for (const Ray& r : conformance_rays(scene, 300, 4))
            n += accel.intersect(r).t != want.intersect(r).t || accel.occluded(r) != want.occluded(r);
        return n;
    };
    for (const std::string& spec : specs) {
        // Brute force with the spec's own triangle test: the two tests differ at shared edges.
        const std::string brute_spec = "brute:isect=" + isect_of(spec);
        const std::unique_ptr<Accel> brute = build_accel(brute_spec, base), flat_brute = build_accel(brute_spec, flat);
        const std::unique_ptr<Accel> accel = build_accel(spec, base);
        accel->refit(flat);
        EXPECT_EQ(differ(*accel, *flat_brute, flat), 0u) << spec << " refitted flat";
        accel->refit(base);
        EXPECT_EQ(differ(*accel, *brute, base), 0u) << spec << " refitted back";
        // Built flat, the triangle gains its interior back: rays through it must find it.
        const std::unique_ptr<Accel> from_flat = build_accel(spec, flat);
        from_flat->refit(base);
        EXPECT_EQ(differ(*from_flat, *brute, base), 0u) << spec << " built flat, refitted to the base";
        EXPECT_EQ(from_flat->intersect(through).prim, 10u) << spec;
    }
}

/// An empty scene refits to an empty structure; a scene of one triangle moved far away is found
/// there and no longer where it was.
TEST(RefitRefusals, EmptyAndSingleTriangleScenes) {
    Scene one;
    one.name = "one triangle";
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2};
    one.add_mesh(m);
    Scene moved = one;
    moved.set_vertices(0, std::vector<Vec3>{{100, 0, 0}, {101, 0, 0}, {100, 1, 0}});
    for (const std::string spec : {"bvh", "bvh8", "obb", "bvh8:quality=high"}) {
        const std::unique_ptr<Accel> empty = build_accel(spec, Scene{});
        EXPECT_NO_THROW(empty->refit(Scene{})) << spec;
        EXPECT_TRUE(empty->bounds().empty()) << spec;
        const std::unique_ptr<Accel> accel = build_accel(spec, one);
        accel->refit(moved);
        EXPECT_EQ(accel->intersect(Ray{{100.2f, 0.2f, 1}, 0.0f, {0, 0, -1}, kInfinity}).prim, 0u) << spec;
        EXPECT_EQ(accel->intersect(Ray{{0.2f, 0.2f, 1}, 0.0f, {0, 0, -1}, kInfinity}).prim, kNoPrim) << spec;
        EXPECT_FALSE(accel->occluded(Ray{{0.2f, 0.2f, 1}, 0.0f, {0, 0, -1}, kInfinity})) << spec;
        EXPECT_EQ(accel->bounds().min.x, 100.0f) << spec;
    }
}

/// Every other structure says it cannot refit, names itself and says to rebuild.
TEST(RefitRefusals, OtherStructuresSayToRebuild) {
    const Scene base = generated_scene();
    size_t checked = 0;
    for (const AccelInfo& info : accel_registry()) {
        if (info.name == "bvh" || info.name == "bvh8" || info.name == "obb") continue;
        const std::unique_ptr<Accel> accel = build_accel(info.name, base);
        EXPECT_FALSE(accel->refittable()) << info.name;
        try {
            accel->refit(base);
            ADD_FAILURE() << info.name << " refit() did not refuse";
        } catch (const Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("'" + accel->spec() + "'"), std::string::npos) << what;
            EXPECT_NE(what.find("rebuild"), std::string::npos) << what;
        }
        ++checked;
    }
    EXPECT_GE(checked, 5u);
}

/// Child order after a refit (issue 45: a refit that kept stale traversal hints would answer
/// right but visit more nodes). The scene mirrored in x (exact in float): a rebuild there is the
/// build's mirror image, and the refitted tree, whose order hints must follow the mirror, visits
/// no more nodes than the rebuild (2% for tie-breaks the builders may take differently).
TEST(RefitOrder, AMirroredSceneVisitsNoMoreNodesThanARebuild) {
    const Scene base = generated_scene();
    Scene mirrored = base;
    std::vector<Vec3> v = mirrored.mesh.positions;
    for (Vec3& p : v) p.x = -p.x;
    mirrored.set_vertices(0, v);
    const std::vector<Ray> rays = conformance_rays(mirrored, 3000, 6);
    for (const std::string spec : {"bvh:traversal=ordered-centroid", "bvh:traversal=ordered-axis", "bvh",
                                   "bvh:builder=ploc,traversal=ordered-axis", "bvh:builder=ploc,traversal=ordered-centroid",
                                   "bvh:optimize=reinsertion,traversal=ordered-axis"}) {
        const std::unique_ptr<Accel> refitted = build_accel(spec, base), rebuilt = build_accel(spec, mirrored);
        refitted->refit(mirrored);
        RayCounters a, b;
        for (const Ray& r : rays) {
            EXPECT_EQ(refitted->intersect(r, a).t, rebuilt->intersect(r, b).t) << spec;
        }
        std::printf("[ order    ] %s: %llu nodes after the refit, %llu after a rebuild\n", spec.c_str(),
                    (unsigned long long)a.nodes, (unsigned long long)b.nodes);
        EXPECT_LE(double(a.nodes), 1.02 * double(b.nodes)) << spec;
    }
}

/// bvh8's FMA slab test is conservative only while every plane of the tree lies within the
/// context's plane bounds (docs/bvh8.md): after a refit that grows the scene a thousandfold they
/// must be the new tree's, not the build's (rays rarely show stale ones: the slack covers most).
TEST(RefitBvh8, PlaneBoundsFollowTheMove) {
    const Scene base = generated_scene();
    const Scene grown = moved_scene(base, Motion::Grow);
    std::vector<std::string> specs = {"bvh8:quality=high"};
    for (Isa isa : cpu_isas()) specs.push_back(std::string("bvh8:isa=") + isa_name(isa));
    for (const std::string& spec : specs) {
        const std::unique_ptr<Accel> accel = build_accel(spec, base);
        accel->refit(grown);
        const auto* tree = dynamic_cast<const Bvh8<Triangles<TriangleTest::Moller>>*>(accel.get());
        ASSERT_NE(tree, nullptr) << spec;
        const bvh8::TraceContext& ctx = tree->trace_context();
        bvh8::TraceContext want;
        bvh8::set_plane_bounds(want, tree->tree().nodes.data(), tree->tree().nodes.size());
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(ctx.plane_lo[a], want.plane_lo[a]) << spec << " axis " << a;
            EXPECT_EQ(ctx.plane_hi[a], want.plane_hi[a]) << spec << " axis " << a;
        }
        EXPECT_EQ(ctx.nodes, tree->tree().nodes.data()) << spec;
        EXPECT_EQ(ctx.blocks, tree->blocks().data()) << spec;
    }
}

/// The README's refit example ("Moving vertices: refit"), on the bunny, checked against brute force.
TEST(RefitReadme, ExampleRefitsLikeBruteForce) {
    if (shared_scene_dir().empty()) GTEST_SKIP() << shared_scenes_missing_message();
    thicket::Scene scene = thicket::load_scene(shared_scene_dir() + "/bunny.ply");
    auto accel = thicket::build_accel("bvh8", scene);
    std::vector<thicket::Vec3> v = scene.mesh.positions;
    for (thicket::Vec3& p : v) p.y += 0.1f * p.x * p.x * 100.0f;
    scene.set_vertices(0, v);
    accel->refit(scene);
    const std::unique_ptr<Accel> brute = build_accel("brute", scene);
    size_t differ = 0;
    for (const Ray& r : conformance_rays(scene, 300, 2)) differ += accel->intersect(r).t != brute->intersect(r).t;
    EXPECT_EQ(differ, 0u);
}

}  // namespace
}  // namespace thicket::testing::refit_test
