#pragma once
/// Double-precision helpers shared by the shape kernels: a 3-vector of doubles, outward-rounded
/// float boxes, and a safeguarded Newton solver on a bracket. Kernels compute in double and
/// report float results, so a float ray meets a surface with far less rounding than its own.
#include <cmath>

#include "thicket/core/aabb.h"

namespace thicket {

struct DVec3 {
    double x = 0, y = 0, z = 0;

    constexpr DVec3() = default;
    constexpr DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit DVec3(Vec3 v) : x(v.x), y(v.y), z(v.z) {}

    constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr DVec3 operator+(DVec3 b) const { return {x + b.x, y + b.y, z + b.z}; }
    constexpr DVec3 operator-(DVec3 b) const { return {x - b.x, y - b.y, z - b.z}; }
    constexpr DVec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr DVec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    constexpr DVec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 to_float() const { return {float(x), float(y), float(z)}; }
};

constexpr double dot(DVec3 a, DVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr DVec3 cross(DVec3 a, DVec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(DVec3 v) { return std::sqrt(dot(v, v)); }
inline DVec3 normalize(DVec3 v) { return v / length(v); }

inline constexpr double kTwoPi = 6.283185307179586476925286766559;

/// An angle in radians as a fraction of a full turn in [0, 1) (atan2's (-pi, pi] wrapped).
inline float turn_fraction(double angle) {
    double f = angle / kTwoPi + 0.0;  // + 0.0 turns -0 into +0
    if (f < 0.0) f += 1.0;
    const float u = float(f);
    return u < 1.0f ? u : 0.0f;  // 1 - 1e-17 rounds to 1.0f: the same direction as 0
}

/// The float box enclosing the double box [lo, hi]: each bound is rounded outward, so a surface
/// computed in double never pokes out of its float bounds (c + r in float can round inward).
inline Aabb outward_box(DVec3 lo, DVec3 hi) {
    Aabb b;
    for (int k = 0; k < 3; ++k) {
        const float l = float(lo[k]), h = float(hi[k]);
        b.min[k] = double(l) > lo[k] ? std::nextafter(l, -INFINITY) : l;
        b.max[k] = double(h) < hi[k] ? std::nextafter(h, INFINITY) : h;
    }
    return b;
}

/// Root of f in [lo, hi] where f(lo) and f(hi) have opposite signs (f_lo is f(lo)), to within
/// `tol`, by Newton steps that fall back to bisection whenever a step leaves the bracket or does
/// not shrink fast enough (Numerical Recipes' rtsafe). Deterministic: a pure function of its
/// arguments, so the same root comes back whatever the caller's search window.
template <class F, class DF>
double bracketed_newton(F&& f, DF&& df, double lo, double hi, double f_lo, double tol) {
    double x = 0.5 * (lo + hi);
    double step = hi - lo, last_step = step;
    for (int i = 0; i < 200; ++i) {
        const double fx = f(x);
        if (fx == 0.0) return x;
        if ((fx < 0.0) == (f_lo < 0.0)) {
            lo = x;
            f_lo = fx;
        } else {
            hi = x;
        }
        if (!(hi - lo > tol)) return 0.5 * (lo + hi);
        double next = x - fx / df(x);
        // Bisect if Newton leaves the bracket (NaN included) or does not halve the step before last.
        if (!(next > lo && next < hi) || std::fabs(next - x) > 0.5 * std::fabs(last_step)) next = 0.5 * (lo + hi);
        last_step = step;
        step = next - x;
        if (!(std::fabs(step) > tol)) return next;
        x = next;
    }
    return x;
}

}  // namespace thicket
