#include "thicket/bench/growth_fit.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "thicket/core/error.h"

namespace thicket {

PowerFit fit_power_law(std::span<const double> n, std::span<const double> y, double min_n) {
    if (n.size() != y.size())
        throw Error("fit_power_law: " + std::to_string(n.size()) + " sizes but " + std::to_string(y.size()) +
                    " values");
    auto usable = [&](size_t i) {
        return n[i] >= min_n && n[i] > 0.0 && y[i] > 0.0 && std::isfinite(n[i]) && std::isfinite(y[i]);
    };
    PowerFit fit;
    double sx = 0.0, sy = 0.0;
    for (size_t i = 0; i < n.size(); ++i) {
        if (!usable(i)) continue;
        fit.min_n = fit.points ? std::min(fit.min_n, n[i]) : n[i];
        fit.max_n = fit.points ? std::max(fit.max_n, n[i]) : n[i];
        ++fit.points;
        sx += std::log(n[i]);
        sy += std::log(y[i]);
    }
    if (!fit.valid()) {
        fit.exponent = fit.coefficient = fit.r2 = std::numeric_limits<double>::quiet_NaN();
        return fit;
    }
    // Centred sums: the logs of 10^6 are large next to their spread, so sum(x^2) - n*mean^2 would
    // lose digits.
    const double mx = sx / double(fit.points), my = sy / double(fit.points);
    double sxx = 0.0, sxy = 0.0, syy = 0.0;
    for (size_t i = 0; i < n.size(); ++i) {
        if (!usable(i)) continue;
        const double dx = std::log(n[i]) - mx, dy = std::log(y[i]) - my;
        sxx += dx * dx;
        sxy += dx * dy;
        syy += dy * dy;
    }
    fit.exponent = sxy / sxx;
    fit.coefficient = std::exp(my - fit.exponent * mx);
    // A perfect line through constant y (syy = 0) is explained fully.
    fit.r2 = syy > 0.0 ? (sxy * sxy) / (sxx * syy) : 1.0;
    return fit;
}

}  // namespace thicket
