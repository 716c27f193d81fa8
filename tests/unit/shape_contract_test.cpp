// Every kernel of Shape keeps the contract the structures rely on (prims/shape.h, docs/shapes.md):
// the root it reports does not depend on tmax (a structure calls it with its current closest hit
// as tmax and must get brute force's answer bit for bit), hits lie in [tmin, tmax] and in the
// ray's interval through the bounds, and normals are finite unit vectors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include "thicket/core/ray_box.h"
#include "thicket/prims/control_mesh.h"
#include "thicket/prims/shapes.h"
#include "thicket/prims/teapot_patches.h"

namespace thicket::shape_contract_test {
namespace {

ImplicitOptions at(Vec3 center, float scale, ImplicitMethod method = ImplicitMethod::interval) {
    ImplicitOptions o;
    o.center = center;
    o.scale = scale;
    o.method = method;
    return o;
}

/// At least one sample of every alternative of Shape, away from the origin and not unit-sized.
std::vector<Shape> samples() {
    std::vector<Shape> out;
    out.push_back(Sphere{{1, 2, 3}, 0.7f});
    out.push_back(Torus{{-1, 0, 2}, normalize(Vec3{1, 2, 0.5f}), 0.8f, 0.25f});
    out.push_back(teapot_patches()[5]);   // body
    out.push_back(teapot_patches()[20]);  // lid, collapsed to the knob
    ControlMesh cage = cube_control_mesh();
    for (Vec3& p : cage.positions) p = Vec3{2, -1, 0} + p * 0.6f;
    out.push_back(SubdivisionSurface(cage, 2));
    out.push_back(Implicit("tangle-cube", at({0, 1, -2}, 0.4f)));
    out.push_back(Implicit("barth-sextic", at({0, 1, -2}, 0.8f), 1.0));
    out.push_back(Implicit("tangle-cube", at({1, 1, 1}, 0.3f, ImplicitMethod::sphere_tracing)));
    out.push_back(Blobs(BlobSum{{Blob{{0, 0, 0}, 1.0, 1.0}, Blob{{0.9, 0.3, 0}, 0.8, 1.0}}, 0.3}, at({-2, 0, 0}, 0.7f)));
    Julia::Params julia;
    julia.march.center = {0.5f, -0.5f, 1};
    julia.march.scale = 0.8f;
    julia.march.iterations = 8;
    out.push_back(Julia(julia));
    Mandelbulb::Params bulb;
    bulb.march.center = {-0.5f, 0.5f, -1};
    bulb.march.scale = 0.9f;
    bulb.march.iterations = 6;
    out.push_back(Mandelbulb(bulb));
    return out;
}

bool intersect(const Shape& s, const Ray& ray, float tmax, ShapeHit& hit) {
    return std::visit([&](const auto& k) { return k.intersect(ray, tmax, hit); }, s);
}

/// Rays from around the shape's box aimed at random points inside it (most hit), some with
/// tmin > 0.
std::vector<Ray> rays_at(const Shape& s, std::mt19937& rng, int count) {
    const Aabb b = shape_bounds(s);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    auto in_box = [&](Vec3 lo, Vec3 hi) { return Vec3{lo.x + (hi.x - lo.x) * u(rng), lo.y + (hi.y - lo.y) * u(rng), lo.z + (hi.z - lo.z) * u(rng)}; };
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        const Vec3 e = b.extent();
        const Vec3 o = in_box(b.min - e * 1.5f, b.max + e * 1.5f);
        const Vec3 target = in_box(b.min + e * 0.25f, b.max - e * 0.25f);
        rays.push_back({o, (i % 3 == 0) ? 0.1f * u(rng) : 0.0f, target - o, kInfinity});
    }
    return rays;
}

TEST(ShapeContract, EveryKernelHasASample) {
    std::set<size_t> kinds;
    for (const Shape& s : samples()) kinds.insert(s.index());
    EXPECT_EQ(kinds.size(), std::variant_size_v<Shape>) << "add a sample of the new kernel to samples()";
}

TEST(ShapeContract, RootsDoNotDependOnTmax) {
    std::mt19937 rng(17);
    for (const Shape& s : samples()) {
        int hits = 0;
        for (const Ray& ray : rays_at(s, rng, 120)) {
            ShapeHit first;
            if (!intersect(s, ray, kInfinity, first)) continue;
            ++hits;
            // Any tmax at or beyond the first root gives the same root, bit for bit.
            for (float tmax : {first.t, std::nextafter(first.t, kInfinity), first.t * 1.0001f + 1e-30f, first.t * 1.5f,
                               first.t * 4.0f}) {
                ShapeHit again;
                ASSERT_TRUE(intersect(s, ray, tmax, again)) << shape_name(s) << " tmax " << tmax << " t " << first.t;
                EXPECT_EQ(again.t, first.t) << shape_name(s) << " tmax " << tmax;
                EXPECT_EQ(again.u, first.u) << shape_name(s);
                EXPECT_EQ(again.v, first.v) << shape_name(s);
            }
            // A window that ends before it holds no root (the first root is the first).
            const float before = first.t * 0.99f;
            ShapeHit none;
            if (before >= ray.tmin) {
                EXPECT_FALSE(intersect(s, ray, before, none)) << shape_name(s) << " t " << first.t << " found " << none.t;
            }
        }
        EXPECT_GE(hits, 20) << shape_name(s) << ": too few hits for the test to mean anything";
    }
}

TEST(ShapeContract, HitsLieInTheWindowAndBoundsWithUnitNormals) {
    std::mt19937 rng(29);
    for (const Shape& s : samples()) {
        for (Ray ray : rays_at(s, rng, 80)) {
            ShapeHit h;
            ray.tmax = 2.0f;  // the target is at t = 1; some roots lie beyond the window
            if (!intersect(s, ray, ray.tmax, h)) continue;
            EXPECT_GE(h.t, ray.tmin) << shape_name(s);
            EXPECT_LE(h.t, ray.tmax) << shape_name(s);
            EXPECT_TRUE(hit_within_bounds(ray, h.t, shape_bounds(s))) << shape_name(s) << " t " << h.t;
            const Vec3 n = shape_normal(s, ray.org + ray.dir * h.t, h.u, h.v);
            ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z)) << shape_name(s);
            EXPECT_NEAR(length(n), 1.0f, 1e-4f) << shape_name(s);
        }
    }
}

TEST(ShapeContract, NamesAreTheJsonTypes) {
    std::set<std::string> names;
    for (const Shape& s : samples()) names.insert(shape_name(s));
    const std::set<std::string> expected{"sphere", "torus", "bezier", "subdivision", "implicit", "blobs", "julia", "mandelbulb"};
    EXPECT_EQ(names, expected);
}

}  // namespace
}  // namespace thicket::shape_contract_test
