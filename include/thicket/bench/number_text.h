#pragma once
/// Numbers as the bench and compare tables print them.
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <string>

namespace thicket {

/// One double through a printf format.
inline std::string printf_string(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

/// About three significant digits, for rates and per-ray averages; tiny rates (brute force on a
/// large scene) keep two significant digits rather than rounding to zero. `missing` for NaN/inf.
inline std::string three_digits(double v, const std::string& missing) {
    if (!std::isfinite(v)) return missing;
    if (v == 0.0) return "0";
    const double a = std::fabs(v);
    if (a < 0.1) return printf_string("%.2g", v);
    return printf_string(a >= 100 ? "%.0f" : a >= 10 ? "%.1f" : a >= 1 ? "%.2f" : "%.3f", v);
}

/// 1234567 as "1,234,567".
inline std::string grouped(size_t n) {
    const std::string digits = std::to_string(n);
    std::string out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

/// "66,454 triangles", or with shapes "69,491 primitives (69,451 triangles, 40 shapes)".
inline std::string primitives_text(size_t primitives, size_t shapes) {
    if (shapes == 0) return grouped(primitives) + " triangles";
    return grouped(primitives) + " primitives (" + grouped(primitives - shapes) + " triangles, " + grouped(shapes) +
           (shapes == 1 ? " shape)" : " shapes)");
}

}  // namespace thicket
