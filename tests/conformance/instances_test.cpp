// Two-level instancing (instances/instances.h) against brute force over the flattened scene: the
// covering set of every registered structure's variants (variant_cover.h) as the bottom level,
// under instances with translation, rotation, uniform and anisotropic scale, shear and mirroring
// (negative determinant), two coincident instances; closest t within a tolerance (the ray is
// transformed, not the triangles, so the roundings differ), the same instance, geometry and
// primitive (or another that the ray really hits at that t), world normals, occlusion, batches.
// Then what must be refused (near-singular and non-finite transforms) and what must not be
// rebuilt (set_transform keeps the bottom levels; memory follows unique geometry).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "support/variant_cover.h"
#include "thicket/instances/instances.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace thicket::testing::instances_test {
namespace {

#ifdef THICKET_SANITIZED
constexpr size_t kRays = 250;
#else
constexpr size_t kRays = 800;
#endif

/// Geometry 0: a closed UV sphere of radius 1; 1: a wavy sheet; 2: a tetrahedron.
std::shared_ptr<const Scene> prototypes() {
    auto scene = std::make_shared<Scene>();
    scene->name = "instance-prototypes";
    TriangleMesh sphere;
    const int rings = 10, segments = 16;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const double theta = M_PI * r / rings, phi = 2.0 * M_PI * s / segments;
            sphere.positions.push_back({float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                                        float(std::sin(theta) * std::sin(phi))});
        }
    auto at = [&](int r, int s) { return uint32_t(r * segments + (s % segments)); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            if (r != 0) sphere.indices.insert(sphere.indices.end(), {at(r, s), at(r + 1, s), at(r, s + 1)});
            if (r != rings - 1)
                sphere.indices.insert(sphere.indices.end(), {at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
        }
    scene->add_mesh(sphere);
    TriangleMesh sheet;
    const int n = 8;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
            const float x = -1.0f + 2.0f * float(i) / n, z = -1.0f + 2.0f * float(j) / n;
            sheet.positions.push_back({x, 0.2f * std::sin(3.0f * x) * std::cos(2.0f * z), z});
        }
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const uint32_t a = uint32_t(i * (n + 1) + j), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            sheet.indices.insert(sheet.indices.end(), {a, c, b, b, c, d});
        }
    scene->add_mesh(sheet);
    TriangleMesh tet;
    tet.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tet.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    scene->add_mesh(tet);
    return scene;
}

Affine affine(std::initializer_list<float> rows) {
    Affine t;
    auto it = rows.begin();
    for (auto& row : t.m)
        for (float& x : row) x = *it++;
    return t;
}

/// Every kind of transform the instances must handle; the comment says which.
std::vector<Instance> instances() {
    const float c = std::cos(0.7f), s = std::sin(0.7f);
    return {
        {0, affine({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0})},                    // identity
        {0, affine({1, 0, 0, 4, 0, 1, 0, 1, 0, 0, 1, -2})},                   // translation
        {1, affine({2.5f, 0, 0, -4, 0, 2.5f, 0, 0, 0, 0, 2.5f, 1})},          // uniform scale
        {0, affine({5, 0, 0, 0, 0, 0.3f, 0, -3, 0, 0, 1, 3})},                // anisotropic scale
        {0, affine({1, 0.8f, 0.3f, 3, 0, 1, 0.5f, 3, 0, 0, 1, 0})},           // shear
        {0, affine({-1, 0, 0, -3, 0, 1, 0, 3, 0, 0, 1, 0})},                  // mirror
        {2, affine({c, 0, s, 0, 0, -1.5f, 0, -2, -s, 0, c, -3})},             // rotation and mirror
        {1, affine({c, -s, 0, 1, s, c, 0, 0, 0, 0, 1, 5})},                   // rotation
        {2, affine({0.5f, 0.4f, 0, 6, 0, -0.7f, 0.2f, -1, 0.3f, 0, 1.2f, 1})}, // shear, mirror
        {2, affine({0.5f, 0.4f, 0, 6, 0, -0.7f, 0.2f, -1, 0.3f, 0, 1.2f, 1})}, // coincident copy
    };
}

/// Where ray `r` meets triangle (a, b, c), in double (Moller-Trumbore); NaN if it does not.
double hit_t(const Ray& r, Vec3 a, Vec3 b, Vec3 c) {
    const double o[3] = {r.org.x, r.org.y, r.org.z}, d[3] = {r.dir.x, r.dir.y, r.dir.z};
    const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
    const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
    const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0.0) return NAN;
    const double s[3] = {o[0] - a.x, o[1] - a.y, o[2] - a.z};
    const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
    const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    const double tol = 1e-6;
    if (u < -tol || v < -tol || u + v > 1.0 + tol) return NAN;
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
}

/// Rays aimed at interior points of random triangles of the flattened scene from random places
/// around it, a quarter with a tmax window that ends before or just after the aimed point, and
/// some in random directions.
std::vector<Ray> rays_for(const Scene& flat, size_t count) {
    std::mt19937 rng(27);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const Aabb b = flat.bounds();
    const Vec3 lo = b.min - b.extent() * 0.3f, span = b.extent() * 1.6f;
    std::vector<Ray> rays;
    for (size_t i = 0; i < count; ++i) {
        Ray r;
        r.org = lo + Vec3(unit(rng) * span.x, unit(rng) * span.y, unit(rng) * span.z);
        const size_t tri = size_t(unit(rng) * float(flat.mesh.triangle_count())) % flat.mesh.triangle_count();
        float u = 0.1f + 0.8f * unit(rng), v = 0.1f + 0.8f * unit(rng);
        if (u + v > 0.9f) u = 0.9f - u * 0.5f, v = 0.9f - u - 0.05f;
        const Vec3 target = flat.mesh.vertex(tri, 0) * (1.0f - u - v) + flat.mesh.vertex(tri, 1) * u +
                            flat.mesh.vertex(tri, 2) * v;
        r.dir = i % 10 == 9 ? Vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f) : target - r.org;
        if (i % 4 == 1) r.tmax = unit(rng) * 1.2f;
        if (i % 8 == 3) r.tmin = unit(rng) * 0.3f;
        rays.push_back(r);
    }
    return rays;
}

/// "" if `got` (from the instanced structure) answers ray `r` as `want` (brute force over the
/// flattened scene) does, else what differs.
std::string disagreement(const InstancedAccel& accel, const Scene& flat, const Ray& r, const Hit& got,
                         const Hit& want, double condition) {
    if (got.found() != want.found())
        return std::string("hit ") + (got.found() ? "found" : "missed") + ", brute force's " +
               (want.found() ? "found" : "missed");
    if (!got.found()) return "";
    // float's rounding of t grows with the transform's condition number (the ray is carried by
    // the inverse) and, at grazing incidence, with 1 / cos of the angle to the surface.
    const Vec3 n = flat.geometric_normal(want.prim);
    const double cosine = std::fabs(dot(n, r.dir)) / (double(length(n)) * length(r.dir));
    const double tol = std::max(2e-5, 8 * condition * 6e-8) * std::max(1.0, double(std::fabs(want.t))) /
                       std::max(cosine, 1e-3);
    if (std::fabs(double(got.t) - want.t) > tol)
        return "t " + std::to_string(got.t) + ", brute force " + std::to_string(want.t);
    if (got.prim >= flat.primitive_count()) return "primitive " + std::to_string(got.prim) + " out of range";
    const Geometry fg = flat.geometry(flat.geometry_of(got.prim));
    const InstanceHit where = accel.locate(got.prim);
    if (where.instance != flat.geometry_of(got.prim) || where.prim != got.prim - fg.first ||
        where.geometry != accel.instances()[where.instance].geometry ||
        where.scene_prim != accel.prototypes().geometry(where.geometry).first + where.prim)
        return "locate(" + std::to_string(got.prim) + ") names instance " + std::to_string(where.instance) +
               " primitive " + std::to_string(where.prim);
    if (got.prim != want.prim) {
        // Coincident instances (or a shared edge): another primitive really hit at that t is right.
        const double t = hit_t(r, flat.mesh.vertex(got.prim, 0), flat.mesh.vertex(got.prim, 1),
                               flat.mesh.vertex(got.prim, 2));
        if (!(std::fabs(t - want.t) <= tol))
            return "primitive " + std::to_string(got.prim) + ", brute force " + std::to_string(want.prim);
        return "";
    }
    const Vec3 g = accel.normal(r, got), m = flat.normal(r, want);
    if (!(dot(g, m) > 0.9999f))
        return "normal (" + std::to_string(g.x) + ", " + std::to_string(g.y) + ", " + std::to_string(g.z) +
               "), flattened (" + std::to_string(m.x) + ", " + std::to_string(m.y) + ", " + std::to_string(m.z) + ")";
    return "";
}

/// Checks `accel` on `rays` against brute force over the flattened scene; "" when all agree.
std::string check_against_flattened(const InstancedAccel& accel, const std::vector<Ray>& rays) {
    const Scene flat = flatten_instances(accel.prototypes(), accel.instances());
    const std::unique_ptr<Accel> brute = build_accel("brute", flat);
    std::vector<Hit> batch(rays.size());
    accel.intersect(rays, batch);
    std::vector<uint8_t> batch_occluded(rays.size());
    accel.occluded(rays, batch_occluded);
    double condition = 0.0;
    for (const Instance& inst : accel.instances()) condition = std::max(condition, transform_condition(inst.transform));
    std::string errors;
    size_t bad = 0, hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit got = accel.intersect(rays[i]), want = brute->intersect(rays[i]);
        hits += want.found();
        RayCounters counters;
        std::string what = disagreement(accel, flat, rays[i], got, want, condition);
        if (what.empty() && (batch[i].t != got.t || batch[i].prim != got.prim)) what = "batch differs from one ray";
        if (what.empty() && accel.intersect(rays[i], counters).prim != got.prim) what = "counting pass differs";
        if (what.empty() && accel.occluded(rays[i]) != brute->occluded(rays[i])) what = "occlusion differs";
        if (what.empty() && bool(batch_occluded[i]) != accel.occluded(rays[i])) what = "batch occlusion differs";
        if (!what.empty() && bad++ < 5) errors += "  ray " + std::to_string(i) + ": " + what + "\n";
    }
    // The rays are aimed at the surfaces: a structure that misses everything must not pass.
    if (hits * 2 < rays.size()) return accel.spec() + ": only " + std::to_string(hits) + " rays hit";
    return bad == 0 ? "" : accel.spec() + ": " + std::to_string(bad) + " of " + std::to_string(rays.size()) +
                               " rays disagree:\n" + errors;
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
    std::string name = "instances_";
    for (char ch : info.param) name += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
    return name;
}

class Instances : public ::testing::TestWithParam<std::string> {};

TEST_P(Instances, AgreeWithBruteForceOverTheFlattenedScene) {
    const InstancedAccel accel(prototypes(), instances(), GetParam());
    const Scene flat = flatten_instances(accel.prototypes(), accel.instances());
    EXPECT_EQ(check_against_flattened(accel, rays_for(flat, kRays)), "");
}

INSTANTIATE_TEST_SUITE_P(BottomLevels, Instances, ::testing::ValuesIn(covering_variants(all_accel_variants())),
                         test_name);

TEST(InstanceRefusals, NearSingularAndNonFiniteTransformsAreRefused) {
    // Condition number about 1.4e5: beyond kMaxTransformCondition.
    const Affine flat_z = affine({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1e-5f, 0});
    try {
        InstancedAccel accel(prototypes(), {{0, flat_z}}, "bvh");
        FAIL() << "a near-singular transform was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("instance 0: the transform is singular or nearly so"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("limit is 10000"), std::string::npos) << e.what();
    }
    // Just inside the limit (condition about 7.1e3) is taken, and answers like the flattened scene.
    const Affine thin = affine({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2e-4f, 0});
    EXPECT_LT(transform_condition(thin), kMaxTransformCondition);
    {
        const InstancedAccel accel(prototypes(), {{1, thin}}, "bvh");
        const Scene flat = flatten_instances(accel.prototypes(), accel.instances());
        EXPECT_EQ(check_against_flattened(accel, rays_for(flat, 200)), "");
    }
    Affine nan_entry;
    nan_entry.m[1][3] = NAN;
    EXPECT_THROW(InstancedAccel(prototypes(), {{0, nan_entry}}, "bvh"), Error);
    EXPECT_THROW(InstancedAccel(prototypes(), {{0, affine({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0})}}, "bvh"), Error);
    EXPECT_THROW(InstancedAccel(prototypes(), {{3, Affine{}}}, "bvh"), Error);  // no geometry 3

    // A refused set_transform changes nothing.
    InstancedAccel accel(prototypes(), instances(), "bvh");
    EXPECT_THROW(accel.set_transform(2, flat_z), Error);
    EXPECT_THROW(accel.set_transform(99, Affine{}), Error);
    // Well conditioned but carrying the sphere past float's range: refused, the old one kept.
    EXPECT_THROW(accel.set_transform(1, affine({1e38f, 0, 0, 3e38f, 0, 1e38f, 0, 0, 0, 0, 1e38f, 0})), Error);
    EXPECT_THROW(accel.add_instance({1, affine({1e38f, 0, 0, 3e38f, 0, 1e38f, 0, 0, 0, 0, 1e38f, 0})}), Error);
    EXPECT_EQ(accel.instances().size(), instances().size());
    const Scene flat = flatten_instances(accel.prototypes(), accel.instances());
    EXPECT_EQ(check_against_flattened(accel, rays_for(flat, 200)), "");
}

TEST(InstanceUpdates, SetTransformRebuildsOnlyTheTopLevel) {
    InstancedAccel accel(prototypes(), instances(), "bvh8");
    const Accel* sphere = accel.bottom(0);
    const Accel* tet = accel.bottom(2);
    accel.set_transform(0, affine({0, -2, 0, 1, 2, 0, 0, -1, 0, 0, -2, 2}));  // rotate, scale, mirror
    accel.set_transform(6, affine({1, 0, 0, 8, 0, 1, 0, 8, 0, 0, 1, 8}));
    EXPECT_EQ(accel.bottom(0), sphere);
    EXPECT_EQ(accel.bottom(2), tet);
    const uint32_t added = accel.add_instance({1, affine({1, 0, 0, 0, 0, -1, 0, 6, 0, 0, 1, 0})});
    EXPECT_EQ(added, instances().size());
    EXPECT_EQ(accel.bottom(0), sphere);
    const Scene flat = flatten_instances(accel.prototypes(), accel.instances());
    EXPECT_EQ(check_against_flattened(accel, rays_for(flat, 400)), "");
}

TEST(InstanceUpdates, RaysVisitOnlyTheBoxesTheyEnter) {
    // A row of 200 spheres along x; unbounded rays (tmax = +inf) that miss the row, and one
    // along it that enters every box: the first must visit nothing, and one across the row
    // must visit about a path down the top level, not the whole of it.
    std::vector<Instance> row;
    for (int i = 0; i < 200; ++i) row.push_back({0, affine({1, 0, 0, 3.0f * float(i), 0, 1, 0, 0, 0, 0, 1, 0})});
    const InstancedAccel accel(prototypes(), row, "bvh");
    RayCounters beside, across;
    EXPECT_FALSE(accel.intersect(Ray{{0.0f, 5.0f, 0.0f}, 0.0f, {1.0f, 0.0f, 0.0f}}, beside).found());
    EXPECT_EQ(beside.nodes, 1u);  // the root, none of whose children's boxes it enters
    EXPECT_EQ(beside.prims, 0u);
    EXPECT_TRUE(accel.intersect(Ray{{300.0f, 0.5f, -5.0f}, 0.0f, {0.0f, 0.0f, 1.0f}}, across).found());
    EXPECT_LT(across.nodes, 100u);  // the top level alone has 399 nodes
}

TEST(InstanceUpdates, MemoryFollowsUniqueGeometry) {
    std::vector<Instance> many;
    for (int i = 0; i < 200; ++i)
        many.push_back({0, affine({1, 0, 0, 3.0f * float(i % 20), 0, 1, 0, 3.0f * float(i / 20), 0, 0, 1, 0})});
    const InstancedAccel one(prototypes(), {many[0]}, "bvh");
    const InstancedAccel all(prototypes(), many, "bvh");
    const AccelStats s1 = one.stats(), s200 = all.stats();
    EXPECT_EQ(all.unique_primitives(), one.unique_primitives());
    EXPECT_EQ(all.instanced_primitives(), 200 * one.instanced_primitives());
    // The bottom level is held once: 199 more instances add their records and top-level nodes,
    // far less than one more copy of the structure and its triangles each: a 64-byte leaf record,
    // the 52-byte instance, its 48-byte inverse, 24-byte world box and 4-byte id, and about 0.4
    // top-level nodes of 256 bytes (uncompressed: instance_top.h says why).
    const size_t per_instance = (s200.bytes + s200.primitive_bytes - s1.bytes - s1.primitive_bytes) / 199;
    EXPECT_LT(per_instance, 320u);
    EXPECT_LT(20 * per_instance, s1.bytes + s1.primitive_bytes);
    EXPECT_EQ(s200.primitive_bytes, s1.primitive_bytes);
}

}  // namespace
}  // namespace thicket::testing::instances_test
