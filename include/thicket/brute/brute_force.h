#pragma once
/// The brute-force reference: tests every primitive. Every other structure is checked against it.
#include "thicket/accel/accel.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {

template <PrimitiveSet Prims>
class BruteForce final : public AccelBase<BruteForce<Prims>> {
public:
    explicit BruteForce(Prims prims) : prims_(std::move(prims)) {
        for (uint32_t i = 0; i < prims_.size(); ++i) bounds_.grow(prims_.bounds(i));
    }

    Aabb bounds() const override { return bounds_; }

    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        Hit hit = miss_for(ray);
        for (uint32_t i = 0, n = uint32_t(prims_.size()); i < n; ++i) {
            counters.prim();
            prims_.intersect(i, ray, hit);
        }
        return hit;
    }

    template <class C>
    bool any(const Ray& ray, C& counters) const {
        for (uint32_t i = 0, n = uint32_t(prims_.size()); i < n; ++i) {
            counters.prim();
            if (prims_.occludes(i, ray)) return true;
        }
        return false;
    }

    AccelStats stats() const override {
        AccelStats s = this->base_stats();
        s.primitives = prims_.size();
        s.primitive_bytes = prims_.bytes();
        s.sah_cost = kSahIntersectionCost * double(prims_.size());  // one leaf holding everything
        return s;
    }

private:
    Prims prims_;
    Aabb bounds_;
};

}  // namespace thicket
