#pragma once
// Double-precision references for the implicit-surface tests: f and its gradient at points, the
// first root along a line by dense sampling, closeness to the surface, projection onto it.
#include <cmath>
#include <optional>

#include "thicket/prims/implicit.h"

namespace thicket::implicit_reference {

// ---- double-precision helpers over a surface ---------------------------------------------

template <class S>
double f_at(const S& s, const Vec3d& p) {
    return s.value(p[0], p[1], p[2]);
}
template <class S>
Vec3d grad_at(const S& s, const Vec3d& p) {
    const auto g = s.gradient(p[0], p[1], p[2]);
    return {g[0], g[1], g[2]};
}
inline double norm(const Vec3d& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
inline double dotd(const Vec3d& a, const Vec3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3d axpy(const Vec3d& p, double s, const Vec3d& d) { return {p[0] + s * d[0], p[1] + s * d[1], p[2] + s * d[2]}; }
inline Vec3 to_float(const Vec3d& v) { return Vec3(float(v[0]), float(v[1]), float(v[2])); }

/// The first root of f along the line in [a, b], found by dense sampling: a sign change between
/// samples is bisected; a local minimum of |f| without a sign change (a near-tangency the
/// samples straddle) is minimized by golden section and, if f reaches 0 there, its first root
/// is bisected. `from_dip` reports whether the root came from such a minimum (a grazing root).
template <class S>
std::optional<double> reference_first_root(const S& s, const Line3d& l, double a, double b, int n = 8192,
                                           bool* from_dip = nullptr) {
    auto f = [&](double t) { return f_at(s, l.at(t)); };
    auto bisect = [&](double lo, double hi) {
        const bool lo_neg = f(lo) < 0.0;
        for (int i = 0; i < 200; ++i) {
            const double m = 0.5 * (lo + hi);
            if (!(m > lo && m < hi)) break;
            const double fm = f(m);
            if (fm == 0.0) return m;
            ((fm < 0.0) == lo_neg ? lo : hi) = m;
        }
        return 0.5 * (lo + hi);
    };
    if (from_dip) *from_dip = false;
    double t2 = a, f2 = f(a);  // two samples back
    if (f2 == 0.0) return a;
    double t1 = a, f1 = f2;
    for (int i = 1; i <= n; ++i) {
        const double t = i == n ? b : a + (b - a) * i / n;
        const double ft = f(t);
        if (ft == 0.0) return t;
        if ((ft < 0.0) != (f1 < 0.0)) return bisect(t1, t);
        if (i >= 2 && std::fabs(f1) < std::fabs(f2) && std::fabs(f1) <= std::fabs(ft)) {
            const double sgn = f1 < 0.0 ? -1.0 : 1.0;
            double lo = t2, hi = t;  // golden section for the minimum of sgn * f
            const double g = 0.5 * (std::sqrt(5.0) - 1.0);
            for (int k = 0; k < 100; ++k) {
                const double c = hi - g * (hi - lo), d = lo + g * (hi - lo);
                (sgn * f(c) < sgn * f(d) ? hi : lo) = (sgn * f(c) < sgn * f(d) ? d : c);
            }
            const double tm = 0.5 * (lo + hi);
            if (sgn * f(tm) <= 0.0) {
                if (from_dip) *from_dip = true;
                return f(tm) == 0.0 ? tm : bisect(t2, tm);
            }
        }
        t2 = t1, f2 = f1;
        t1 = t, f1 = ft;
    }
    return std::nullopt;
}

/// Whether the line point at t lies within `dist` of the surface: f changes sign within
/// [t - w, t + w], or the first-order distance |f| / |grad f| gets below dist there.
template <class S>
bool near_surface(const S& s, const Line3d& l, double t, double w, double dist) {
    double prev = f_at(s, l.at(t - w));
    for (int i = 0; i <= 256; ++i) {
        const Vec3d p = l.at(t - w + 2.0 * w * i / 256);
        const double fv = f_at(s, p);
        if (fv == 0.0 || (fv < 0.0) != (prev < 0.0)) return true;
        const double g = norm(grad_at(s, p));
        if (g > 0.0 && std::fabs(fv) / g <= dist) return true;
        prev = fv;
    }
    return false;
}

/// A point of the surface near p: Newton steps along the gradient (nullopt if it does not
/// converge inside the box).
template <class S>
std::optional<Vec3d> project_to_surface(const S& s, Vec3d p, const Box3d& box) {
    for (int i = 0; i < 60; ++i) {
        const double fv = f_at(s, p);
        const Vec3d g = grad_at(s, p);
        const double g2 = dotd(g, g);
        if (!(g2 > 1e-12)) return std::nullopt;
        p = axpy(p, -fv / g2, g);
        if (std::fabs(fv) / std::sqrt(g2) < 1e-13) break;
    }
    if (std::fabs(f_at(s, p)) / norm(grad_at(s, p)) > 1e-10) return std::nullopt;
    for (int k = 0; k < 3; ++k)
        if (p[k] < box.lo[k] || p[k] > box.hi[k]) return std::nullopt;
    return p;
}

template <class S>
Box3d object_box(const ImplicitKernel<S>& k) {
    return k.surface().box();
}

/// World point of an object point.
inline Vec3d to_world(const ImplicitOptions& o, const Vec3d& q) {
    return {o.center.x + o.scale * q[0], o.center.y + o.scale * q[1], o.center.z + o.scale * q[2]};
}

/// The placement the tests use: off-center and scaled, so object and world space differ.
inline ImplicitOptions placed(ImplicitMethod m = ImplicitMethod::interval) {
    ImplicitOptions o;
    o.center = Vec3(0.5f, -1.25f, 2.0f);
    o.scale = 1.5f;
    o.method = m;
    return o;
}

inline BlobSum four_blobs() {
    BlobSum s;
    s.threshold = 0.3;
    s.blobs = {{{0, 0, 0}, 1.0, 1.0}, {{0.8, 0.3, 0}, 0.8, 1.0}, {{-0.5, 0.7, 0.3}, 0.7, 0.8}, {{0.2, -0.6, 0.4}, 0.9, 1.2}};
    return s;
}

}  // namespace thicket::implicit_reference
