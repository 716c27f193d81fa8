#pragma once
/// The double-precision structures' share of Accel (`precision=double`), as AccelBase is the float
/// ones': float rays are widened to double and their hits rounded back, double rays answered as
/// they are. A structure provides
///   template <class C> HitD closest(const RayD&, C& counters) const;
///   template <class C> bool any(const RayD&, C& counters) const;
/// (C is RayCounters or NoCounters) and befriends AccelBaseD if they are private.
#include "thicket/accel/accel.h"
#include "thicket/core/ray_double.h"

namespace thicket {

template <class Derived>
class AccelBaseD : public Accel {
public:
    using Accel::intersect;
    using Accel::intersect_double;
    using Accel::occluded;
    using Accel::occluded_double;

    Hit intersect(const Ray& ray) const final {
        NoCounters none;
        return to_hit(self().closest(to_double(ray), none));
    }
    Hit intersect(const Ray& ray, RayCounters& c) const final { return to_hit(self().closest(to_double(ray), c)); }
    bool occluded(const Ray& ray) const final {
        NoCounters none;
        return self().any(to_double(ray), none);
    }
    bool occluded(const Ray& ray, RayCounters& c) const final { return self().any(to_double(ray), c); }
    bool double_precision() const final { return true; }
    HitD intersect_double(const RayD& ray) const final {
        NoCounters none;
        return self().closest(ray, none);
    }
    bool occluded_double(const RayD& ray) const final {
        NoCounters none;
        return self().any(ray, none);
    }

private:
    const Derived& self() const { return static_cast<const Derived&>(*this); }
};

}  // namespace thicket
