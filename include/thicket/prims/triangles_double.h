#pragma once
/// The triangle primitive set in double precision: what `precision=double` structures test.
/// Vertices are the mesh's double coordinates when it has them (TriangleMesh::positions_double),
/// else its float positions widened exactly.
#include <cstdint>
#include <vector>

#include "thicket/core/ray_double.h"
#include "thicket/geometry/mesh.h"

namespace thicket {

template <TriangleTest Test = TriangleTest::Moller>
class TrianglesD {
public:
    struct Tri {
        Vec3d v0, v1, v2;
    };

    static constexpr TriangleTest kTest = Test;

    explicit TrianglesD(const TriangleMesh& mesh) {
        tris_.resize(mesh.triangle_count());
        for (size_t i = 0; i < tris_.size(); ++i)
            tris_[i] = {mesh.vertex_double(i, 0), mesh.vertex_double(i, 1), mesh.vertex_double(i, 2)};
    }

    size_t size() const { return tris_.size(); }
    size_t bytes() const { return tris_.size() * sizeof(Tri); }
    AabbD bounds(uint32_t i) const { return box_of(tris_[i]); }
    Vec3d centroid(uint32_t i) const { return (tris_[i].v0 + tris_[i].v1 + tris_[i].v2) * (1.0 / 3.0); }

    /// Closest-hit update: if triangle i is hit within [ray.tmin, hit.t], overwrite hit.
    bool intersect(uint32_t i, const RayD& ray, HitD& hit) const {
        TriangleHitD th;
        const Tri& tri = tris_[i];
        if (!intersect_triangle<Test>(tri.v0, tri.v1, tri.v2, ray, hit.t, th) || !plausible(tri, ray, th.t))
            return false;
        hit = {th.t, th.u, th.v, i};
        return true;
    }
    /// Any-hit: is triangle i hit within [ray.tmin, ray.tmax]?
    bool occludes(uint32_t i, const RayD& ray) const {
        TriangleHitD th;
        const Tri& tri = tris_[i];
        return intersect_triangle<Test>(tri.v0, tri.v1, tri.v2, ray, ray.tmax, th) && plausible(tri, ray, th.t);
    }

    /// The rule of Triangles::plausible in double: the triangle has an interior, and t lies in
    /// the ray's interval through its box, so a box hierarchy never culls a hit brute force keeps.
    static bool plausible(const Tri& tri, const RayD& ray, double t) {
        if (degenerate(tri)) return false;
        const AabbD b = box_of(tri);
        return ray_box_entry(RayBoxQueryD(ray), b.min, b.max, t, t) != std::numeric_limits<double>::infinity();
    }
    static AabbD box_of(const Tri& tri) {
        AabbD b;
        b.grow(tri.v0);
        b.grow(tri.v1);
        b.grow(tri.v2);
        return b;
    }
    /// Edges parallel to within double precision: no interior (Triangles::degenerate, in double).
    static bool degenerate(const Tri& tri) {
        const Vec3d e1 = tri.v1 - tri.v0, e2 = tri.v2 - tri.v0;
        const Vec3d n = cross(e1, e2);
        return !(dot(n, n) > kDegenerateSine2 * dot(e1, e1) * dot(e2, e2));
    }
    static constexpr double kDegenerateSine2 = 1e-24;  ///< sine 1e-12 squared

private:
    std::vector<Tri> tris_;
};

}  // namespace thicket
