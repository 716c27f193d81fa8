#pragma once
/// The triangle primitive set: the fast path every structure is tuned for. Vertices are stored
/// by value, three per triangle (36 bytes), so a leaf test touches one cache line per triangle.
#include <array>
#include <cstdint>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/closest_point.h"
#include "thicket/core/ray_box.h"
#include "thicket/core/triangle.h"
#include "thicket/prims/clip.h"
#include "thicket/geometry/mesh.h"
#include "thicket/core/huge_pages.h"

namespace thicket {

template <TriangleTest Test = TriangleTest::Moller>
class Triangles {
public:
    struct Tri {
        Vec3 v0, v1, v2;
    };

    Triangles() = default;
    explicit Triangles(const TriangleMesh& mesh) {
        reserve_huge(tris_, mesh.triangle_count());
        tris_.resize(mesh.triangle_count());
        for (size_t i = 0; i < tris_.size(); ++i)
            tris_[i] = {mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2)};
    }

    static constexpr const char* kind() { return Test == TriangleTest::Moller ? "moller" : "watertight"; }
    size_t size() const { return tris_.size(); }
    size_t bytes() const { return tris_.size() * sizeof(Tri); }

    Aabb bounds(uint32_t i) const { return box_of(tris_[i]); }
    Vec3 centroid(uint32_t i) const { return (tris_[i].v0 + tris_[i].v1 + tris_[i].v2) * (1.0f / 3.0f); }

    /// The vertices of triangle i (BSP planes, fragments).
    std::array<Vec3, 3> triangle(uint32_t i) const { return {tris_[i].v0, tris_[i].v1, tris_[i].v2}; }
    /// Exact bounds of the part of triangle i inside `box` (perfect splits).
    Aabb clip(uint32_t i, const Aabb& box) const {
        return clip_triangle_to_box(tris_[i].v0, tris_[i].v1, tris_[i].v2, box);
    }

    /// Closest-hit update: if primitive i is hit within [ray.tmin, hit.t], overwrite hit.
    bool intersect(uint32_t i, const Ray& ray, Hit& hit) const { return intersect_using<Test>(i, ray, hit); }
    /// intersect() with the test T (the mixed set, which picks its test at run time, stores its
    /// triangles as one Triangles and calls the test the spec asks for).
    template <TriangleTest T>
    bool intersect_using(uint32_t i, const Ray& ray, Hit& hit) const {
        TriangleHit th;
        const Tri& tri = tris_[i];
        if (!intersect_triangle<T>(tri.v0, tri.v1, tri.v2, ray, hit.t, th) || !plausible(tri, ray, th.t))
            return false;
        hit = {th.t, th.u, th.v, i};
        return true;
    }
    /// The closest point of triangle i to p (degenerate triangles too: they have no interior for
    /// rays to hit, but their points are still on the surface).
    NearestPoint closest_point(uint32_t i, const Vec3& p) const {
        const Tri& tri = tris_[i];
        const TrianglePoint q = closest_point_on_triangle(p, tri.v0, tri.v1, tri.v2);
        return {q.point, point_distance(p, q.point), q.u, q.v, i};
    }
    /// Any-hit: is primitive i hit within [ray.tmin, ray.tmax]?
    bool occludes(uint32_t i, const Ray& ray) const { return occludes_using<Test>(i, ray); }
    template <TriangleTest T>
    bool occludes_using(uint32_t i, const Ray& ray) const {
        TriangleHit th;
        const Tri& tri = tris_[i];
        return intersect_triangle<T>(tri.v0, tri.v1, tri.v2, ray, ray.tmax, th) && plausible(tri, ray, th.t);
    }

    /// Whether a hit the test reported is real: the triangle has an interior, and t lies in the
    /// ray's interval through the triangle's box (hit_within_bounds). Checked only once a test
    /// reports a hit, so the common path pays nothing.
    static bool plausible(const Tri& tri, const Ray& ray, float t) {
        return !degenerate(tri) && hit_within_bounds(ray, t, box_of(tri));
    }

    static Aabb box_of(const Tri& tri) {
        Aabb b;
        b.grow(tri.v0);
        b.grow(tri.v1);
        b.grow(tri.v2);
        return b;
    }

    /// A triangle whose edges are parallel to within float precision has no interior: the
    /// ray/triangle tests' results on it are rounding noise (hits reported far outside the
    /// triangle's own box, which brute force would accept and any box hierarchy would cull).
    static bool degenerate(const Tri& tri) {
        const Vec3 e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
        const Vec3 n = cross(e1, e2);
        // In double: the fourth powers of edge lengths overflow float for coordinates past ~1e9.
        const double sine2 = double(kDegenerateSine) * kDegenerateSine;
        return !(double(dot(n, n)) > sine2 * double(dot(e1, e1)) * double(dot(e2, e2)));
    }
    static constexpr float kDegenerateSine = 1e-6f;  ///< |e1 x e2| / (|e1| |e2|) at or below: degenerate

private:
    std::vector<Tri> tris_;
};

}  // namespace thicket
