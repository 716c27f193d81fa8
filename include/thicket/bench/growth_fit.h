#pragma once
/// How build time grows with the number of primitives: a least-squares fit of a power law
/// y = c * n^k in log-log space, the measured counterpart of the lecture's O(n), O(n log n), O(n^2).
/// n log n fits k slightly above 1 (about 1 + 1/ln n: 1.09 over 10^4..10^6).
#include <cstddef>
#include <limits>
#include <span>

namespace thicket {

struct PowerFit {
    double exponent = std::numeric_limits<double>::quiet_NaN();     ///< k
    double coefficient = std::numeric_limits<double>::quiet_NaN();  ///< c
    double r2 = std::numeric_limits<double>::quiet_NaN();  ///< coefficient of determination of the log-log line
    size_t points = 0;                                     ///< points the fit used
    double min_n = 0.0, max_n = 0.0;                       ///< smallest and largest n used

    /// Whether there was a line to fit: at least two points with distinct n.
    bool valid() const { return points >= 2 && max_n > min_n; }
};

/// Fits log y = log c + k log n by least squares over the points (n[i], y[i]) with n[i] >= min_n
/// and both n[i] and y[i] finite and positive; the others are ignored. Without two usable points of
/// distinct n the result is not valid() and its figures are NaN. Throws Error when n and y differ
/// in length.
PowerFit fit_power_law(std::span<const double> n, std::span<const double> y, double min_n = 0.0);

}  // namespace thicket
