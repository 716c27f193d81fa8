#include "thicket/scene/instance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "thicket/core/error.h"

namespace thicket {

namespace {

/// det and the adjugate's rows of A in double (A^-1 = adj / det).
double det3(const double a[3][3]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

void linear_part(const Affine& t, double a[3][3]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) a[i][j] = t.m[i][j];
}

/// A^-1 in double; false for a singular A.
bool invert3(const double a[3][3], double inv[3][3]) {
    const double d = det3(a);
    if (!(d != 0.0) || !std::isfinite(d)) return false;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            // Cofactor of a[j][i]: the rows and columns other than j and i, cyclically.
            const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            inv[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / d;
        }
    return true;
}

double frobenius(const double a[3][3]) {
    double s = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) s += a[i][j] * a[i][j];
    return std::sqrt(s);
}

}  // namespace

double transform_condition(const Affine& t) {
    for (const auto& row : t.m)
        for (float x : row)
            if (!std::isfinite(x)) return std::numeric_limits<double>::quiet_NaN();
    double a[3][3], inv[3][3];
    linear_part(t, a);
    if (!invert3(a, inv)) return std::numeric_limits<double>::infinity();
    return frobenius(a) * frobenius(inv);
}

double transform_determinant(const Affine& t) {
    double a[3][3];
    linear_part(t, a);
    return det3(a);
}

Affine checked_inverse(const Affine& t, const std::string& what) {
    const double cond = transform_condition(t);
    if (std::isnan(cond)) throw Error(what + ": the transform has a non-finite entry");
    if (!(cond <= kMaxTransformCondition)) {
        std::ostringstream s;
        s << what << ": the transform is singular or nearly so (condition number ||A||*||A^-1|| = " << cond
          << ", the limit is " << kMaxTransformCondition << "); refusing it";
        throw Error(s.str());
    }
    double a[3][3], inv[3][3];
    linear_part(t, a);
    invert3(a, inv);
    Affine r;
    for (int i = 0; i < 3; ++i) {
        double b = 0.0;
        for (int j = 0; j < 3; ++j) {
            r.m[i][j] = float(inv[i][j]);
            b -= inv[i][j] * double(t.m[j][3]);
        }
        r.m[i][3] = float(b);
    }
    return r;
}

Aabb transform_box(const Affine& t, const Aabb& box) {
    Aabb out;
    if (box.empty()) return out;
    for (int c = 0; c < 8; ++c)
        out.grow(t.point({(c & 1) ? box.max.x : box.min.x, (c & 2) ? box.max.y : box.min.y,
                          (c & 4) ? box.max.z : box.min.z}));
    // The corners' images are rounded; pad by more than that rounding so that every point of the
    // exactly transformed box stays inside.
    const Vec3 e = max(abs(out.min), abs(out.max));
    const float pad = 1e-6f * std::max(e.x, std::max(e.y, e.z));
    out.min = out.min - Vec3(pad);
    out.max = out.max + Vec3(pad);
    return out;
}

}  // namespace thicket
