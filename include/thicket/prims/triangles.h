#pragma once
/// The triangle primitive set: the fast path every structure is tuned for. Vertices are stored
/// by value, three per triangle (36 bytes), so a leaf test touches one cache line per triangle.
#include <cstdint>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/ray_box.h"
#include "thicket/core/triangle.h"
#include "thicket/scene/mesh.h"

namespace thicket {

template <TriangleTest Test = TriangleTest::Moller>
class Triangles {
public:
    struct Tri {
        Vec3 v0, v1, v2;
    };

    Triangles() = default;
    explicit Triangles(const TriangleMesh& mesh) {
        tris_.resize(mesh.triangle_count());
        for (size_t i = 0; i < tris_.size(); ++i)
            tris_[i] = {mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2)};
    }

    static constexpr const char* kind() { return Test == TriangleTest::Moller ? "moller" : "watertight"; }
    size_t size() const { return tris_.size(); }
    size_t bytes() const { return tris_.size() * sizeof(Tri); }

    Aabb bounds(uint32_t i) const {
        Aabb b;
        b.grow(tris_[i].v0);
        b.grow(tris_[i].v1);
        b.grow(tris_[i].v2);
        return b;
    }
    Vec3 centroid(uint32_t i) const { return (tris_[i].v0 + tris_[i].v1 + tris_[i].v2) * (1.0f / 3.0f); }

    /// Closest-hit update: if primitive i is hit within [ray.tmin, hit.t], overwrite hit.
    /// Hits obey hit_within_bounds() (checked only once a hit is found: off the common path).
    bool intersect(uint32_t i, const Ray& ray, Hit& hit) const {
        TriangleHit th;
        if (!intersect_triangle<Test>(tris_[i].v0, tris_[i].v1, tris_[i].v2, ray, hit.t, th)) return false;
        if (!hit_within_bounds(ray, th.t, bounds(i))) return false;
        hit = {th.t, th.u, th.v, i};
        return true;
    }
    /// Any-hit: is primitive i hit within [ray.tmin, ray.tmax]?
    bool occludes(uint32_t i, const Ray& ray) const {
        TriangleHit th;
        return intersect_triangle<Test>(tris_[i].v0, tris_[i].v1, tris_[i].v2, ray, ray.tmax, th) &&
               hit_within_bounds(ray, th.t, bounds(i));
    }

private:
    std::vector<Tri> tris_;
};

}  // namespace thicket
