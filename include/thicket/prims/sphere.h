#pragma once
/// The sphere kernel (models ShapeKernel). The quadratic is solved in double with the two
/// precision fixes of Haines, Guenther & Akenine-Moeller (Ray Tracing Gems ch. 7): the
/// discriminant from the distance of the ray's line to the centre (no b^2 - ac cancellation, so
/// small or distant spheres are not lost), and the near root as c/q (no b - sqrt(b^2 - ac)
/// cancellation). From inside, the first root is behind the origin and the far root is reported.
///
/// Surface parameters: u = phi / 2pi, phi the right-handed angle about +y from +x (towards -z);
/// v = theta / pi, theta the angle from +y (v = 0 at the +y pole, 1 at the -y pole).
#include <algorithm>
#include <cmath>

#include "thicket/prims/shape.h"
#include "thicket/prims/shape_util.h"

namespace thicket {

struct Sphere {
    static constexpr const char* kName = "sphere";

    Vec3 center;
    float radius = 1.0f;

    Aabb bounds() const {
        const Vec3d c(center);
        const double r = radius;
        return outward_box(c - Vec3d(r, r, r), c + Vec3d(r, r, r));
    }

    /// First crossing with t in [ray.tmin, tmax]. The roots depend on the ray alone, never on
    /// the window, so every structure gets bit-identical answers to brute force.
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const {
        const Vec3d d(ray.dir), f = Vec3d(ray.org) - Vec3d(center);
        const double a = dot(d, d);
        if (!(a > 0.0)) return false;
        const double r = radius;
        const double b = -dot(f, d);              // a * (parameter of the closest approach)
        const Vec3d l = f + d * (b / a);          // centre to the closest point of the line
        const double disc = r * r - dot(l, l);    // (half chord)^2: no cancellation of b^2 - ac
        if (!(disc >= 0.0)) return false;
        const double q = b + std::copysign(std::sqrt(a * disc), b);
        const double c = dot(f, f) - r * r;
        double t0 = 0.0, t1 = 0.0;
        if (q != 0.0) {
            t0 = c / q;
            t1 = q / a;
            if (t0 > t1) std::swap(t0, t1);
        }
        for (const double t : {t0, t1}) {
            const float tf = float(t);
            if (!(tf >= ray.tmin && tf <= tmax)) continue;
            // The unit normal in double, its angles in float: (u, v) are floats anyway, and
            // float atan2/acos cost a third of double ones.
            const Vec3 n = normalize(f + d * t).to_float();
            hit.t = tf;
            hit.u = turn_fraction(std::atan2(-n.z, n.x));
            hit.v = std::acos(std::clamp(n.y, -1.0f, 1.0f)) * float(2.0 / kTwoPi);
            return true;
        }
        return false;
    }

    /// (p - centre) / radius, computed from (u, v): exact even where the float hit point has
    /// lost the sphere (a tiny sphere far from the origin).
    Vec3 normal(Vec3, float u, float v) const {
        const double phi = kTwoPi * u, theta = kTwoPi / 2 * v;
        return Vec3d(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi)).to_float();
    }
};

static_assert(ShapeKernel<Sphere>);

}  // namespace thicket
