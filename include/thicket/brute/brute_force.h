#pragma once
/// The brute-force reference: tests every primitive. Every other structure is checked against it.
/// Over a double set (`brute:precision=double`, TrianglesD) it is the reference the double BVH is
/// checked against: every triangle tested with double vertices and ray arithmetic.
#include <algorithm>
#include <type_traits>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {

/// Over a PrimitiveSet, or a set in double (kDoublePrimitives).
template <class Prims>
class BruteForce final : public AccelBase<BruteForce<Prims>> {
public:
    static constexpr bool kDoublePrecision = kDoublePrimitives<Prims>;
    static_assert(kDoublePrecision || PrimitiveSet<Prims>);
    using S = std::conditional_t<kDoublePrecision, double, float>;

    explicit BruteForce(Prims prims) : prims_(std::move(prims)) {
        for (uint32_t i = 0; i < prims_.size(); ++i) bounds_.grow(prims_.bounds(i));
    }

    Aabb bounds() const override {
        if constexpr (kDoublePrecision)
            return outward_float_box(bounds_);
        else
            return bounds_;
    }

    template <class C>
    HitT<S> closest(const RayT<S>& ray, C& counters) const {
        HitT<S> hit = miss_for(ray);
        for (uint32_t i = 0, n = uint32_t(prims_.size()); i < n; ++i) {
            counters.prim();
            prims_.intersect(i, ray, hit);
        }
        return hit;
    }

    template <class C>
    bool any(const RayT<S>& ray, C& counters) const {
        for (uint32_t i = 0, n = uint32_t(prims_.size()); i < n; ++i) {
            counters.prim();
            if (prims_.occludes(i, ray)) return true;
        }
        return false;
    }

    using Accel::all_hits;  // the batch form stays visible next to the per-ray override

    /// The reference of all_hits: every root of every primitive (a primitive asked again from just
    /// past each of its roots, as a sphere has two), sorted by t, then merged into crossings by
    /// the rule the default implementation follows (Accel::all_hits, kSameCrossing). A double set
    /// takes that default implementation itself.
    void all_hits(const Ray& ray, std::vector<Hit>& out) const override {
        if constexpr (kDoublePrecision) {
            Accel::all_hits(ray, out);
        } else {
            std::vector<Hit> roots;
            for (uint32_t i = 0, n = uint32_t(prims_.size()); i < n; ++i) {
                step_crossings(ray, [&](const Ray& rest) {
                    Hit hit = miss_for(rest);
                    prims_.intersect(i, rest, hit);
                    return hit;
                }, roots);
            }
            merge_crossings(roots, &out);
        }
    }

    /// The reference of closest_point: every primitive, the lowest id among equally close ones.
    NearestPoint closest_point(const Vec3& p) const override {
        if constexpr (HasClosestPoint<Prims>) {
            NearestPoint best;
            for (uint32_t i = 0, n = uint32_t(prims_.size()); i < n; ++i) {
                const NearestPoint s = prims_.closest_point(i, p);
                // The first of equal distances; at +inf too (a distance beyond float's range), so
                // that such a point still gets a primitive, the one every structure answers.
                if (s.distance < best.distance || (s.distance == best.distance && !best.found())) best = s;
            }
            return best;
        } else {
            return Accel::closest_point(p);  // shapes: refused with the reason
        }
    }
    bool has_closest_point() const override { return HasClosestPoint<Prims>; }

    AccelStats stats() const override {
        AccelStats s = this->base_stats();
        s.primitives = prims_.size();
        s.primitive_bytes = prims_.bytes();
        s.sah_cost = kSahIntersectionCost * double(prims_.size());  // one leaf holding everything
        return s;
    }

private:
    Prims prims_;
    AabbT<S> bounds_;
};

}  // namespace thicket
