#pragma once
/// The torus kernel (models ShapeKernel): the ring torus of points at distance `minor` from the
/// circle of radius `major` around `center` in the plane perpendicular to the unit `axis`
/// (0 < minor < major).
///
/// Robust rather than clever (closed-form quartic solvers lose roots to cancellation): in double,
/// the ray is reparametrized by unit length from its closest approach to the centre and scaled
/// so that major = 1; every root then lies in the chord through the bounding sphere (radius
/// 1 + minor/major), where the quartic's coefficients are of order one, narrowed to the slab
/// that holds the tube (rays through the hole are rejected there without solving). The chord is split at the
/// real roots of q' and q'' (found the same way, recursively), so q is monotone without inflection
/// on each piece; each piece with a sign change holds exactly one root, which Newton reaches
/// from the side that cannot overshoot (polynomial_roots_in). Rays through the hole and grazing
/// rays therefore find every crossing whose sign change survives double rounding.
///
/// Surface parameters, in the frame (e1, e2, axis) with e1 the unit projection of +x onto the
/// torus plane (of +y when the axis is within ~25 degrees of x) and e2 = axis x e1:
/// u = phi / 2pi, phi the angle around the axis from e1 towards e2;
/// v = psi / 2pi, psi the angle around the tube from the outer equator towards +axis.
#include <algorithm>
#include <array>
#include <cmath>

#include "thicket/prims/shape.h"
#include "thicket/prims/shape_util.h"

namespace thicket {

struct Torus {
    static constexpr const char* kName = "torus";

    Vec3 center;
    Vec3 axis{0.0f, 1.0f, 0.0f};  ///< unit length (renormalized in double on use)
    float major = 1.0f;           ///< R: radius of the tube's centre circle
    float minor = 0.25f;          ///< r: radius of the tube, 0 < r < R

    /// The exact box of the torus: along world axis k it reaches R sqrt(1 - axis_k^2) + r.
    Aabb bounds() const {
        const Vec3d a = unit_axis(), c(center);
        Vec3d h;
        const double R = major, r = minor;
        h.x = R * std::sqrt(std::max(0.0, 1.0 - a.x * a.x)) + r;
        h.y = R * std::sqrt(std::max(0.0, 1.0 - a.y * a.y)) + r;
        h.z = R * std::sqrt(std::max(0.0, 1.0 - a.z * a.z)) + r;
        return outward_box(c - h, c + h);
    }

    /// Newton stops once a step is below this (in units of R): the error is then about its square
    /// where the root is simple, and this where it is double (a tangent ray).
    static constexpr double kRootTolerance = 1e-10;
    /// Relative widening of the bounding sphere, slab and hole tests, far above double rounding.
    static constexpr double kMargin = 1e-6;

    /// First crossing with t in [ray.tmin, tmax]; the roots depend on the ray alone.
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const {
        const Vec3d d0(ray.dir);
        const double dlen = length(d0);
        if (!(dlen > 0.0) || !std::isfinite(dlen)) return false;
        const double R = major;
        const Vec3d d = d0 / dlen, a = unit_axis();
        const Vec3d f = Vec3d(ray.org) - Vec3d(center);
        // Closest approach to the centre, in unit length along d: the new origin.
        const double t_mid = -dot(f, d);
        const Vec3d o = (f + d * t_mid) / R;  // scaled: R = 1
        const double rr = double(minor) / R;
        const double reach = (1.0 + rr) * (1.0 + kMargin);  // bounding sphere, widened for rounding
        const double m2 = dot(o, o);
        if (!(m2 <= reach * reach)) return false;
        const double h = std::sqrt(reach * reach - m2);
        double lo = -h, hi = h;
        // Narrow to the slab |p.a| <= rr holding the tube (widened: its ends must lie outside).
        const double g = dot(o, d), ya = dot(o, a), yd = dot(d, a);
        const double slab = rr * (1.0 + kMargin);
        if (yd != 0.0) {
            double s0 = (-slab - ya) / yd, s1 = (slab - ya) / yd;
            if (s0 > s1) std::swap(s0, s1);
            lo = std::max(lo, s0);
            hi = std::min(hi, s1);
            if (!(lo <= hi)) return false;
        } else if (!(std::fabs(ya) <= slab)) {
            return false;
        }
        // Through the hole: the distance from the axis is convex along the ray, so if both ends
        // are inside the cylinder rho < 1 - rr, so is everything between.
        const double hole = (1.0 - rr) * (1.0 - kMargin);
        auto rho2 = [&](double s) {
            const Vec3d p = o + d * s;
            const double y = dot(p, a);
            return dot(p, p) - y * y;
        };
        if (rho2(lo) < hole * hole && rho2(hi) < hole * hole) return false;
        // Every root lies in s in [lo, hi]: skip the solve when that is outside the window
        // (float(...) is monotone, so no root can be inside it then).
        if (float((t_mid + hi * R) / dlen) < ray.tmin || float((t_mid + lo * R) / dlen) > tmax) return false;

        // q(s) = (|p|^2 + 1 - rr^2)^2 - 4 (|p|^2 - (p.a)^2), p = o + s d. g = o.d is zero up to
        // rounding; kept so the coefficients are exact for the o that was computed.
        const double k = m2 + 1.0 - rr * rr;
        const std::array<double, 5> q = {
            k * k - 4.0 * (m2 - ya * ya),                    // s^0
            4.0 * g * k - 8.0 * (g - ya * yd),               // s^1
            4.0 * g * g + 2.0 * k - 4.0 * (1.0 - yd * yd),   // s^2
            4.0 * g,                                         // s^3
            1.0,                                             // s^4
        };
        double roots[4];
        const int n = polynomial_roots_in(q, lo, hi, roots, kRootTolerance);
        for (int i = 0; i < n; ++i) {
            const double s = roots[i];
            const float tf = float((t_mid + s * R) / dlen);
            if (!(tf >= ray.tmin && tf <= tmax)) continue;
            const Vec3d p = o + d * s;
            const double y = dot(p, a);
            const Vec3d w = p - a * y;  // towards the tube's centre circle
            Vec3d e1, e2;
            frame(a, e1, e2);
            hit.t = tf;
            hit.u = turn_fraction(std::atan2(dot(w, e2), dot(w, e1)));
            hit.v = turn_fraction(std::atan2(y, length(w) - 1.0));
            return true;
        }
        return false;
    }

    /// The gradient direction at the point with parameters (u, v): cos psi (cos phi e1 + sin phi
    /// e2) + sin psi axis. Computed from (u, v), exact wherever the float hit point lies.
    Vec3 normal(Vec3, float u, float v) const {
        const Vec3d a = unit_axis();
        Vec3d e1, e2;
        frame(a, e1, e2);
        const double phi = kTwoPi * u, psi = kTwoPi * v;
        const Vec3d radial = e1 * std::cos(phi) + e2 * std::sin(phi);
        return (radial * std::cos(psi) + a * std::sin(psi)).to_float();
    }

    Vec3d unit_axis() const { return normalize(Vec3d(axis)); }

    /// The (e1, e2) of the (u, v) convention: e1 from +x (or +y), e2 = a x e1.
    static void frame(Vec3d a, Vec3d& e1, Vec3d& e2) {
        const Vec3d ref = std::fabs(a.x) < 0.9 ? Vec3d(1, 0, 0) : Vec3d(0, 1, 0);
        e1 = normalize(ref - a * dot(ref, a));
        e2 = cross(a, e1);
    }

};

static_assert(ShapeKernel<Torus>);

}  // namespace thicket
