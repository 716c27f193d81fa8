#pragma once
/// Interval arithmetic over doubles for root isolation (Moore 1966; Mitchell, GI '90): every
/// operation returns an interval that encloses the exact result of the operation on any points
/// of its operands, so an interval that excludes 0 proves that a function has no root there.
///
/// Rounding: results are computed in round-to-nearest and then widened outward instead of
/// switching the FPU rounding mode (which is slow and which compilers may move code across).
/// A correctly rounded result r of an exact value x satisfies |r - x| <= 2^-53 |x|; widening by
/// |r| * k * 2^-52 + 2^-1020 for an expression of k roundings covers that error, the tiny absolute
/// term covers underflow to subnormals. The widening costs about one ulp per operation.
///
/// Domain: finite operands. An overflow yields an infinite or NaN bound; contains_zero() answers
/// true for NaN bounds, so a root finder then keeps subdividing instead of discarding a root.
#include <algorithm>
#include <cmath>

namespace thicket {

struct Interval {
    double lo = 0.0, hi = 0.0;

    constexpr Interval() = default;
    /// The degenerate interval [x, x]: x itself is exact, no widening.
    constexpr explicit Interval(double x) : lo(x), hi(x) {}
    constexpr Interval(double l, double h) : lo(l), hi(h) {}

    constexpr double width() const { return hi - lo; }
    constexpr double mid() const { return 0.5 * (lo + hi); }
    constexpr bool contains(double x) const { return lo <= x && x <= hi; }
};

namespace interval_detail {
inline constexpr double kRel = 0x1p-52;    // one rounding's relative error, with a factor 2 margin
inline constexpr double kAbs = 0x1p-1020;  // covers results that underflow to subnormals

/// A lower bound of the exact value of an expression whose computed value is r after k roundings.
inline double down(double r, int k = 1) { return r - (std::fabs(r) * (k * kRel) + kAbs); }
/// An upper bound, likewise.
inline double up(double r, int k = 1) { return r + (std::fabs(r) * (k * kRel) + kAbs); }

}  // namespace interval_detail

/// x^n by repeated multiplication (n - 1 roundings), n >= 0: the point version of ipow(Interval).
inline double ipow(double x, int n) {
    double r = 1.0;
    for (int i = 0; i < n; ++i) r *= x;
    return r;
}
inline double sqr(double x) { return x * x; }
/// max(0, x): the point version of max0(Interval).
inline double max0(double x) { return std::max(x, 0.0); }

/// Whether 0 may lie in a: true also when a bound is NaN (no conclusion is possible).
inline bool contains_zero(const Interval& a) { return !(a.lo > 0.0 || a.hi < 0.0); }

/// Negation is exact.
inline Interval operator-(const Interval& a) { return {-a.hi, -a.lo}; }

inline Interval operator+(const Interval& a, const Interval& b) {
    return {interval_detail::down(a.lo + b.lo), interval_detail::up(a.hi + b.hi)};
}
inline Interval operator-(const Interval& a, const Interval& b) {
    return {interval_detail::down(a.lo - b.hi), interval_detail::up(a.hi - b.lo)};
}
inline Interval operator+(const Interval& a, double s) { return a + Interval(s); }
inline Interval operator+(double s, const Interval& a) { return a + Interval(s); }
inline Interval operator-(const Interval& a, double s) { return a - Interval(s); }
inline Interval operator-(double s, const Interval& a) { return Interval(s) - a; }

/// Product: the hull of the four endpoint products (the exact range of x*y over a box).
inline Interval operator*(const Interval& a, const Interval& b) {
    const double p0 = a.lo * b.lo, p1 = a.lo * b.hi, p2 = a.hi * b.lo, p3 = a.hi * b.hi;
    return {interval_detail::down(std::min(std::min(p0, p1), std::min(p2, p3))),
            interval_detail::up(std::max(std::max(p0, p1), std::max(p2, p3)))};
}
/// Scaling by an exact scalar: two products instead of four.
inline Interval operator*(const Interval& a, double s) {
    const double p0 = a.lo * s, p1 = a.hi * s;
    return {interval_detail::down(std::min(p0, p1)), interval_detail::up(std::max(p0, p1))};
}
inline Interval operator*(double s, const Interval& a) { return a * s; }

/// Quotient; a divisor that may be 0 gives the whole line (no finite enclosure exists).
inline Interval operator/(const Interval& a, const Interval& b) {
    if (contains_zero(b)) return {-HUGE_VAL, HUGE_VAL};
    const double q0 = a.lo / b.lo, q1 = a.lo / b.hi, q2 = a.hi / b.lo, q3 = a.hi / b.hi;
    return {interval_detail::down(std::min(std::min(q0, q1), std::min(q2, q3))),
            interval_detail::up(std::max(std::max(q0, q1), std::max(q2, q3)))};
}

inline Interval& operator+=(Interval& a, const Interval& b) { return a = a + b; }
inline Interval& operator-=(Interval& a, const Interval& b) { return a = a - b; }
inline Interval& operator*=(Interval& a, const Interval& b) { return a = a * b; }

/// a^n for n >= 0 with the tight even-power rule: an even power of an interval that straddles 0
/// is [0, max(lo^n, hi^n)], not the much wider a*a*...*a (which would let [-1, 1]^2 be [-1, 1]).
/// Odd powers are monotone: [lo^n, hi^n].
inline Interval ipow(const Interval& a, int n) {
    using interval_detail::down, interval_detail::up;
    if (n <= 0) return Interval(1.0);
    if (n == 1) return a;
    const int k = n - 1;  // roundings in ipow
    const double l = ipow(a.lo, n), h = ipow(a.hi, n);
    if (n % 2 == 1) return {down(l, k), up(h, k)};
    if (a.lo >= 0.0) return {std::max(0.0, down(l, k)), up(h, k)};
    if (a.hi <= 0.0) return {std::max(0.0, down(h, k)), up(l, k)};
    return {0.0, up(std::max(l, h), k)};
}
/// a^2 with the even-power rule.
inline Interval sqr(const Interval& a) { return ipow(a, 2); }

/// Square root of the non-negative part of a (negative values have no real root and are
/// ignored); [0, 0] if a lies entirely below 0. (Not named sqrt: an overload in namespace thicket
/// would hide ::sqrt from unqualified calls elsewhere in the namespace.)
inline Interval sqrt_nonneg(const Interval& a) {
    const double l = std::max(a.lo, 0.0), h = std::max(a.hi, 0.0);
    return {std::max(0.0, interval_detail::down(std::sqrt(l))), interval_detail::up(std::sqrt(h))};
}

/// max(0, a): the clamp of piecewise-polynomial kernels. Monotone, so endpoint-wise and exact.
inline Interval max0(const Interval& a) { return {std::max(a.lo, 0.0), std::max(a.hi, 0.0)}; }

/// Common part of two enclosures of the same quantity (both are valid, so their intersection
/// is). If rounding made them disjoint, the hull keeps enclosure rather than returning nothing.
inline Interval intersect(const Interval& a, const Interval& b) {
    const Interval r{std::max(a.lo, b.lo), std::min(a.hi, b.hi)};
    return r.lo <= r.hi ? r : Interval{std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}

/// The hull of two intervals.
inline Interval hull(const Interval& a, const Interval& b) {
    return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}

}  // namespace thicket
