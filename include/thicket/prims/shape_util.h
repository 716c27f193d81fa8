#pragma once
/// Double-precision helpers shared by the shape kernels: a 3-vector of doubles, outward-rounded
/// float boxes, and the real roots of a polynomial in an interval. Kernels compute in double and
/// report float results, so a float ray meets a surface with far less rounding than its own.
#include <array>
#include <cmath>
#include <cstddef>
#include <utility>

#include "thicket/core/aabb.h"
#include "thicket/core/vec3.h"

namespace thicket {

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
inline Aabb outward_box(Vec3d lo, Vec3d hi) {
    Aabb b;
    for (int k = 0; k < 3; ++k) {
        const float l = float(lo[k]), h = float(hi[k]);
        b.min[k] = double(l) > lo[k] ? std::nextafter(l, -INFINITY) : l;
        b.max[k] = double(h) < hi[k] ? std::nextafter(h, INFINITY) : h;
    }
    return b;
}

/// Value at x of the polynomial with coefficients c (ascending powers), by Horner's rule.
template <size_t N>
constexpr double polynomial(const std::array<double, N>& c, double x) {
    double r = c[N - 1];
    for (size_t i = N - 1; i-- > 0;) r = r * x + c[i];
    return r;
}

template <size_t N>
constexpr std::array<double, N - 1> derivative(const std::array<double, N>& c) {
    std::array<double, N - 1> d{};
    for (size_t i = 1; i < N; ++i) d[i - 1] = double(i) * c[i];
    return d;
}

/// Root of p in [lo, hi] where p changes sign and neither p' nor p'' does (a monotone piece
/// without inflection), to within `tol`: Newton from the end where p p'' > 0 (Fourier's
/// condition), which approaches the root from one side, safeguarded as Numerical Recipes'
/// rtsafe (a step that leaves the bracket or does not halve the step before last bisects
/// instead: near a double root Newton only converges linearly). Deterministic: a pure function
/// of its arguments.
template <size_t N>
double monotone_root(const std::array<double, N>& p, double lo, double hi, double p_lo, double tol) {
    const auto dp = derivative(p);
    double x = lo;
    if constexpr (N >= 3) {
        const double curvature = polynomial(derivative(dp), 0.5 * (lo + hi));
        x = curvature == 0.0 ? 0.5 * (lo + hi) : ((p_lo > 0.0) == (curvature > 0.0) ? lo : hi);
    }
    double step = 2.0 * (hi - lo), last_step = step;
    for (int i = 0; i < 100; ++i) {
        const double px = polynomial(p, x);
        if (px == 0.0) return x;
        if ((px < 0.0) == (p_lo < 0.0))
            lo = x;
        else
            hi = x;
        if (!(hi - lo > tol)) return 0.5 * (lo + hi);
        double next = x - px / polynomial(dp, x);
        if (!(next > lo && next < hi) || std::fabs(next - x) > 0.5 * std::fabs(last_step)) next = 0.5 * (lo + hi);
        last_step = step;
        step = next - x;
        // In the quadratic regime the error after this step is ~ step^2: far below tol.
        if (!(std::fabs(step) > tol)) return next;
        x = next;
    }
    return x;
}

/// The real roots of the polynomial p (coefficients by ascending power, leading one non-zero)
/// in [lo, hi], ascending; returns how many (at most N - 1, the size `roots` must have).
/// Quadratics in closed form; higher degrees: the interval is cut at the roots of p' and p''
/// (found the same way, recursively), so p is monotone without inflection on every piece and
/// each piece whose ends differ in sign holds exactly one root (monotone_root). Where p touches
/// zero without changing sign (tangency) a root is found only if p is exactly 0 at a cut.
template <size_t N>
int polynomial_roots_in(const std::array<double, N>& p, double lo, double hi, double* roots, double tol) {
    static_assert(N >= 2);
    if constexpr (N == 2) {
        const double x = -p[0] / p[1];
        if (!(x >= lo && x <= hi)) return 0;
        roots[0] = x;
        return 1;
    } else if constexpr (N == 3) {
        // Closed form without cancellation: q = -(b + sign(b) sqrt(disc)) / 2, roots q/a and c/q.
        const double a = p[2], b = p[1], c = p[0];
        const double disc = b * b - 4.0 * a * c;
        if (!(disc >= 0.0)) return 0;
        const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
        double r[2] = {q / a, q != 0.0 ? c / q : q / a};
        if (r[0] > r[1]) std::swap(r[0], r[1]);
        int found = 0;
        for (const double x : r)
            if (x >= lo && x <= hi && (found == 0 || roots[found - 1] != x)) roots[found++] = x;
        return found;
    } else {
        // Cuts: the ends, and the roots of p' and p'' inside.
        double cuts[2 * N + 2];
        int n = 0;
        cuts[n++] = lo;
        const auto dp = derivative(p);
        double inner[N];
        int k = polynomial_roots_in(dp, lo, hi, inner, tol);
        for (int i = 0; i < k; ++i) cuts[n++] = inner[i];
        if constexpr (N >= 4) {
            k = polynomial_roots_in(derivative(dp), lo, hi, inner, tol);
            for (int i = 0; i < k; ++i) cuts[n++] = inner[i];
        }
        cuts[n++] = hi;
        for (int i = 2; i < n; ++i)  // insertion sort: a handful of values, mostly in order
            for (int j = i; j > 1 && cuts[j - 1] > cuts[j]; --j) std::swap(cuts[j - 1], cuts[j]);
        int found = 0;
        double p_a = polynomial(p, cuts[0]);
        for (int i = 0; i + 1 < n && found < int(N) - 1; ++i) {  // more would be rounding noise
            const double a = cuts[i], b = cuts[i + 1];
            const double p_b = polynomial(p, b);
            if (p_a == 0.0) {
                if (found == 0 || roots[found - 1] != a) roots[found++] = a;
            } else if (p_b != 0.0 && (p_a < 0.0) != (p_b < 0.0)) {
                roots[found++] = monotone_root(p, a, b, p_a, tol);
            }
            p_a = p_b;
        }
        if (p_a == 0.0 && (found == 0 || roots[found - 1] != hi) && found < int(N) - 1) roots[found++] = hi;
        return found;
    }
}

}  // namespace thicket
