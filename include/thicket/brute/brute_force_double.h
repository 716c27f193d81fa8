#pragma once
/// Brute force in double precision (`brute:precision=double`): every triangle tested with double
/// vertices and ray arithmetic; the reference the double BVH is checked against.
#include "thicket/accel/accel_double.h"
#include "thicket/prims/triangles_double.h"

namespace thicket {

template <TriangleTest Test>
class BruteForceD final : public AccelBaseD<BruteForceD<Test>> {
    friend class AccelBaseD<BruteForceD<Test>>;

public:
    explicit BruteForceD(TrianglesD<Test> prims) : prims_(std::move(prims)) {
        for (uint32_t i = 0; i < prims_.size(); ++i) bounds_.grow(prims_.bounds(i));
    }

    Aabb bounds() const override { return outward_float_box(bounds_); }

    AccelStats stats() const override {
        AccelStats s = this->base_stats();
        s.primitives = prims_.size();
        s.primitive_bytes = prims_.bytes();
        s.sah_cost = kSahIntersectionCost * double(prims_.size());
        return s;
    }

private:
    template <class C>
    HitD closest(const RayD& ray, C& counters) const {
        HitD hit = miss_for(ray);
        for (uint32_t i = 0, n = uint32_t(prims_.size()); i < n; ++i) {
            counters.prim();
            prims_.intersect(i, ray, hit);
        }
        return hit;
    }
    template <class C>
    bool any(const RayD& ray, C& counters) const {
        for (uint32_t i = 0, n = uint32_t(prims_.size()); i < n; ++i) {
            counters.prim();
            if (prims_.occludes(i, ray)) return true;
        }
        return false;
    }

    TrianglesD<Test> prims_;
    AabbD bounds_;
};

}  // namespace thicket
