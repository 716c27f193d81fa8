// Interval arithmetic (prims/interval.h): every operation encloses the exact results at points
// of its operands, computed in quad precision (products of doubles are exact there), and the
// even-power rule and the clamp are tight.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "thicket/prims/interval.h"

namespace thicket::interval_test {
namespace {

#if defined(__SIZEOF_FLOAT128__)
using Exact = __float128;  // 113-bit mantissa: x*y of doubles is exact, x+y exact for close exponents
#else
using Exact = long double;
#endif

/// Random intervals of varied magnitudes, signs and widths (degenerate ones included).
Interval random_interval(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::uniform_int_distribution<int> e(-30, 30), kind(0, 5);
    const double scale = std::ldexp(1.0, e(rng));
    double a = u(rng) * scale, b = u(rng) * scale;
    switch (kind(rng)) {
        case 0: b = a; break;                        // a point
        case 1: a = std::fabs(a), b = std::fabs(b); break;  // positive
        case 2: a = -std::fabs(a), b = -std::fabs(b); break;  // negative
        case 3: b = a + std::fabs(b) * 1e-12; break;  // very narrow
        default: break;                              // anything, often straddling 0
    }
    return {std::min(a, b), std::max(a, b)};
}

/// Sample points of an interval: both endpoints and random interior points.
std::vector<double> samples(const Interval& a, std::mt19937_64& rng, int n = 6) {
    std::vector<double> s{a.lo, a.hi, a.mid()};
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < n; ++i) s.push_back(std::clamp(a.lo + u(rng) * (a.hi - a.lo), a.lo, a.hi));
    return s;
}

bool encloses(const Interval& r, Exact x) { return Exact(r.lo) <= x && x <= Exact(r.hi); }

void check_binary(const char* name, const std::function<Interval(Interval, Interval)>& op,
                  const std::function<Exact(Exact, Exact)>& exact, bool skip_zero_divisor = false) {
    std::mt19937_64 rng(11);
    int checked = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const Interval a = random_interval(rng), b = random_interval(rng);
        if (skip_zero_divisor && contains_zero(b)) continue;
        const Interval r = op(a, b);
        ASSERT_LE(r.lo, r.hi) << name;
        for (double x : samples(a, rng))
            for (double y : samples(b, rng)) {
                ++checked;
                ASSERT_TRUE(encloses(r, exact(Exact(x), Exact(y))))
                    << name << " [" << a.lo << ", " << a.hi << "] , [" << b.lo << ", " << b.hi << "] at " << x
                    << ", " << y << " gives [" << r.lo << ", " << r.hi << "]";
            }
    }
    EXPECT_GT(checked, 10000) << name;
}

TEST(Interval, BinaryOperationsEncloseExactResults) {
    check_binary("+", [](Interval a, Interval b) { return a + b; }, [](Exact x, Exact y) { return x + y; });
    check_binary("-", [](Interval a, Interval b) { return a - b; }, [](Exact x, Exact y) { return x - y; });
    check_binary("*", [](Interval a, Interval b) { return a * b; }, [](Exact x, Exact y) { return x * y; });
    check_binary("/", [](Interval a, Interval b) { return a / b; }, [](Exact x, Exact y) { return x / y; }, true);
    check_binary("hull", [](Interval a, Interval b) { return hull(a, b); }, [](Exact x, Exact) { return x; });
}

TEST(Interval, ScalarOperationsEncloseExactResults) {
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> u(-10.0, 10.0);
    for (int trial = 0; trial < 3000; ++trial) {
        const Interval a = random_interval(rng);
        const double s = u(rng);
        for (double x : samples(a, rng)) {
            ASSERT_TRUE(encloses(a * s, Exact(x) * Exact(s)));
            ASSERT_TRUE(encloses(s * a, Exact(x) * Exact(s)));
            ASSERT_TRUE(encloses(a + s, Exact(x) + Exact(s)));
            ASSERT_TRUE(encloses(s - a, Exact(s) - Exact(x)));
            ASSERT_TRUE(encloses(-a, -Exact(x)));
            ASSERT_TRUE(encloses(max0(a), Exact(std::max(x, 0.0))));
        }
    }
}

TEST(Interval, PowersEncloseAndUseTheEvenPowerRule) {
    std::mt19937_64 rng(13);
    for (int n = 0; n <= 9; ++n)
        for (int trial = 0; trial < 1500; ++trial) {
            const Interval a = random_interval(rng);
            const Interval r = ipow(a, n);
            for (double x : samples(a, rng)) {
                Exact p = 1;
                for (int i = 0; i < n; ++i) p *= Exact(x);
                ASSERT_TRUE(encloses(r, p)) << "n=" << n << " [" << a.lo << ", " << a.hi << "] at " << x;
            }
            if (n % 2 == 0) {
                EXPECT_GE(r.lo, 0.0) << "an even power is never negative";
            }
            if (n == 2) {
                const Interval s = sqr(a);
                EXPECT_EQ(s.lo, r.lo);
                EXPECT_EQ(s.hi, r.hi);
            }
        }
}

TEST(Interval, EvenPowerOfStraddlingIntervalIsTight) {
    // The naive product [-2, 1] * [-2, 1] = [-2, 4]; the exact range of x^2 is [0, 4].
    const Interval a{-2.0, 1.0};
    const Interval naive = a * a;
    EXPECT_LT(naive.lo, -1.9);
    const Interval s = sqr(a);
    EXPECT_EQ(s.lo, 0.0);
    EXPECT_NEAR(s.hi, 4.0, 1e-14);
    const Interval p4 = ipow(a, 4);
    EXPECT_EQ(p4.lo, 0.0);
    EXPECT_NEAR(p4.hi, 16.0, 1e-13);
    const Interval p3 = ipow(a, 3);  // odd: monotone
    EXPECT_NEAR(p3.lo, -8.0, 1e-13);
    EXPECT_NEAR(p3.hi, 1.0, 1e-14);
    const Interval neg = sqr(Interval{-3.0, -2.0});
    EXPECT_NEAR(neg.lo, 4.0, 1e-14);
    EXPECT_NEAR(neg.hi, 9.0, 1e-14);
}

TEST(Interval, WideningIsAboutAnUlpPerOperation) {
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<double> u(0.5, 2.0);
    for (int trial = 0; trial < 1000; ++trial) {
        const double x = u(rng), y = u(rng);
        const Interval p = Interval(x) * Interval(y);
        EXPECT_LE(p.width(), 4.0 * std::ldexp(1.0, -52) * (x * y));
        const Interval q = ipow(Interval(x), 6);
        EXPECT_LE(q.width(), 12.0 * 5 * std::ldexp(1.0, -52) * std::pow(x, 6));
    }
}

TEST(Interval, RoundingIsCoveredWhereRoundToNearestIsWrong) {
    // 0.1 + 0.2 rounds to a double above the exact sum of the two doubles: the degenerate
    // interval [r, r] would not enclose it, the widened one does.
    const double r = 0.1 + 0.2;
    const Exact exact = Exact(0.1) + Exact(0.2);
    ASSERT_NE(Exact(r), exact) << "the test needs an inexact sum";
    EXPECT_TRUE(encloses(Interval(0.1) + Interval(0.2), exact));
    // Underflow: a product of two tiny numbers rounds to 0 or a subnormal.
    const double tiny = 1e-200;
    EXPECT_TRUE(encloses(Interval(tiny) * Interval(tiny), Exact(tiny) * Exact(tiny)));
    EXPECT_LT((Interval(tiny) * Interval(tiny)).lo, (Interval(tiny) * Interval(tiny)).hi);
}

TEST(Interval, SqrtEnclosesTheNonNegativePart) {
    std::mt19937_64 rng(15);
    for (int trial = 0; trial < 3000; ++trial) {
        const Interval a = random_interval(rng);
        const Interval r = sqrt_nonneg(a);
        EXPECT_GE(r.lo, 0.0);
        for (double x : samples(a, rng)) {
            if (x < 0.0) continue;
            // y = sqrt(x) exactly iff y^2 = x: check lo^2 <= x <= hi^2 (squares of doubles are exact).
            ASSERT_LE(Exact(r.lo) * Exact(r.lo), Exact(x));
            ASSERT_GE(Exact(r.hi) * Exact(r.hi), Exact(x));
        }
    }
    const Interval neg = sqrt_nonneg(Interval{-4.0, -1.0});
    EXPECT_EQ(neg.lo, 0.0);
    EXPECT_LE(neg.hi, 1e-300);
}

TEST(Interval, DivisionByAnIntervalContainingZeroIsTheWholeLine) {
    const Interval q = Interval{1.0, 2.0} / Interval{-1.0, 1.0};
    EXPECT_TRUE(std::isinf(q.lo) && q.lo < 0);
    EXPECT_TRUE(std::isinf(q.hi) && q.hi > 0);
}

TEST(Interval, ContainsZeroAndIntersection) {
    EXPECT_TRUE(contains_zero({-1.0, 1.0}));
    EXPECT_TRUE(contains_zero({0.0, 1.0}));
    EXPECT_TRUE(contains_zero({-1.0, 0.0}));
    EXPECT_FALSE(contains_zero({1e-300, 1.0}));
    EXPECT_FALSE(contains_zero({-1.0, -1e-300}));
    EXPECT_TRUE(contains_zero({NAN, 1.0})) << "no conclusion from a NaN bound";
    const Interval i = intersect({-1.0, 2.0}, {0.5, 3.0});
    EXPECT_EQ(i.lo, 0.5);
    EXPECT_EQ(i.hi, 2.0);
    // Disjoint enclosures of one quantity can only come from rounding: keep the hull.
    const Interval h = intersect({0.0, 1.0}, {2.0, 3.0});
    EXPECT_EQ(h.lo, 0.0);
    EXPECT_EQ(h.hi, 3.0);
}

}  // namespace
}  // namespace thicket::interval_test
