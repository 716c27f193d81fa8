#pragma once
/// The triangle primitive set: the fast path every structure is tuned for. Vertices are stored
/// by value, three per triangle (36 bytes in float), so a leaf test touches one cache line per
/// triangle. TrianglesD, the same set in double, is what `precision=double` structures test: its
/// vertices are the mesh's double coordinates when it has them (TriangleMesh::positions_double),
/// else its float positions widened exactly.
#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/closest_point.h"
#include "thicket/core/degenerate.h"
#include "thicket/core/ray_box.h"
#include "thicket/core/triangle.h"
#include "thicket/prims/clip.h"
#include "thicket/geometry/mesh.h"
#include "thicket/core/huge_pages.h"

namespace thicket {

template <TriangleTest Test = TriangleTest::Moller, class S = float>
class Triangles {
public:
    using Vec = Vec3T<S>;
    using Box = AabbT<S>;
    using RayS = RayT<S>;
    using HitS = HitT<S>;
    struct Tri {
        Vec v0, v1, v2;
    };

    static constexpr TriangleTest kTest = Test;

    Triangles() = default;
    explicit Triangles(const TriangleMesh& mesh) {
        reserve_huge(tris_, mesh.triangle_count());
        tris_.resize(mesh.triangle_count());
        for (size_t i = 0; i < tris_.size(); ++i) {
            if constexpr (std::is_same_v<S, double>)
                tris_[i] = {mesh.vertex_double(i, 0), mesh.vertex_double(i, 1), mesh.vertex_double(i, 2)};
            else
                tris_[i] = {mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2)};
        }
    }

    static constexpr const char* kind() { return Test == TriangleTest::Moller ? "moller" : "watertight"; }
    size_t size() const { return tris_.size(); }
    size_t bytes() const { return tris_.size() * sizeof(Tri); }

    Box bounds(uint32_t i) const { return box_of(tris_[i]); }
    Vec centroid(uint32_t i) const { return (tris_[i].v0 + tris_[i].v1 + tris_[i].v2) * (S(1) / S(3)); }

    /// The vertices of triangle i (BSP planes, fragments; float only, as are clip and closest_point).
    std::array<Vec3, 3> triangle(uint32_t i) const
        requires std::is_same_v<S, float>
    {
        return {tris_[i].v0, tris_[i].v1, tris_[i].v2};
    }
    /// Exact bounds of the part of triangle i inside `box` (perfect splits).
    Aabb clip(uint32_t i, const Aabb& box) const
        requires std::is_same_v<S, float>
    {
        return clip_triangle_to_box(tris_[i].v0, tris_[i].v1, tris_[i].v2, box);
    }

    /// Closest-hit update: if primitive i is hit within [ray.tmin, hit.t], overwrite hit.
    bool intersect(uint32_t i, const RayS& ray, HitS& hit) const { return intersect_using<Test>(i, ray, hit); }
    /// intersect() with the test T (the mixed set, which picks its test at run time, stores its
    /// triangles as one Triangles and calls the test the spec asks for).
    template <TriangleTest T>
    bool intersect_using(uint32_t i, const RayS& ray, HitS& hit) const {
        TriangleHitT<S> th;
        const Tri& tri = tris_[i];
        if (!intersect_triangle<T>(tri.v0, tri.v1, tri.v2, ray, hit.t, th) || !plausible(tri, ray, th.t))
            return false;
        hit = {th.t, th.u, th.v, i};
        return true;
    }
    /// The closest point of triangle i to p (degenerate triangles too: they have no interior for
    /// rays to hit, but their points are still on the surface).
    NearestPoint closest_point(uint32_t i, const Vec3& p) const
        requires std::is_same_v<S, float>
    {
        const Tri& tri = tris_[i];
        const TrianglePoint q = closest_point_on_triangle(p, tri.v0, tri.v1, tri.v2);
        return {q.point, point_distance(p, q.point), q.u, q.v, i};
    }
    /// Any-hit: is primitive i hit within [ray.tmin, ray.tmax]?
    bool occludes(uint32_t i, const RayS& ray) const { return occludes_using<Test>(i, ray); }
    template <TriangleTest T>
    bool occludes_using(uint32_t i, const RayS& ray) const {
        TriangleHitT<S> th;
        const Tri& tri = tris_[i];
        return intersect_triangle<T>(tri.v0, tri.v1, tri.v2, ray, ray.tmax, th) && plausible(tri, ray, th.t);
    }

    /// Whether a hit the test reported is real: the triangle has an interior, and t lies in the
    /// ray's interval through the triangle's box (hit_within_bounds). Checked only once a test
    /// reports a hit, so the common path pays nothing.
    static bool plausible(const Tri& tri, const RayS& ray, S t) {
        return !degenerate(tri) && hit_within_bounds(ray, t, box_of(tri));
    }

    static Box box_of(const Tri& tri) {
        Box b;
        b.grow(tri.v0);
        b.grow(tri.v1);
        b.grow(tri.v2);
        return b;
    }

    /// A triangle whose edges are parallel to within its precision has no interior: the
    /// ray/triangle tests' results on it are rounding noise (hits reported far outside the
    /// triangle's own box, which brute force would accept and any box hierarchy would cull).
    static bool degenerate(const Tri& tri) {
        const Vec e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
        const Vec n = cross(e1, e2);
        // In double: the fourth powers of edge lengths overflow float for coordinates past ~1e9.
        return !(double(dot(n, n)) > kDegenerateSine2 * double(dot(e1, e1)) * double(dot(e2, e2)));
    }
    /// |e1 x e2| / (|e1| |e2|) at or below: degenerate (core/degenerate.h: 1e-6 in float, 1e-12
    /// in double; the bvh8 kernels test block lanes with the same constant).
    static constexpr S kDegenerateSine = std::is_same_v<S, float> ? S(kDegenerateSineFloat) : S(kDegenerateSineDouble);
    static constexpr double kDegenerateSine2 = std::is_same_v<S, float> ? kDegenerateSine2Float : kDegenerateSine2Double;

private:
    std::vector<Tri> tris_;
};

template <TriangleTest Test = TriangleTest::Moller>
using TrianglesD = Triangles<Test, double>;

}  // namespace thicket
