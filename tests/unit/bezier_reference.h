#pragma once
// A double-precision reference for ray / Bezier patch tests, written independently of the kernel:
// the patch is tessellated densely, every triangle hit along the ray is polished with a 3D
// Newton iteration on S(u, v) - (o + t d), and the nearest polished root is the answer.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "thicket/prims/bezier.h"

namespace thicket::testing {

struct DV {
    double x = 0, y = 0, z = 0;
};
inline DV operator+(DV a, DV b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline DV operator-(DV a, DV b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline DV operator*(DV a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double ddot(DV a, DV b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline DV dcross(DV a, DV b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double dlen(DV a) { return std::sqrt(ddot(a, a)); }
inline DV dv(Vec3 v) { return {v.x, v.y, v.z}; }

/// S, S_u, S_v by the binomial form: sum C(3,i) u^i (1-u)^(3-i) ...
struct RefSample {
    DV p, du, dv;
};
inline RefSample ref_eval(const BezierPatch& patch, double u, double v) {
    auto basis = [](double t, double b[4], double d[4]) {
        const double c[4] = {1, 3, 3, 1};
        for (int i = 0; i < 4; ++i) {
            b[i] = c[i] * std::pow(t, i) * std::pow(1 - t, 3 - i);
            const double a = i > 0 ? i * std::pow(t, i - 1) * std::pow(1 - t, 3 - i) : 0.0;
            const double e = i < 3 ? (3 - i) * std::pow(t, i) * std::pow(1 - t, 2 - i) : 0.0;
            d[i] = c[i] * (a - e);
        }
    };
    double bu[4], du[4], bv[4], dvv[4];
    basis(u, bu, du);
    basis(v, bv, dvv);
    RefSample s;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const DV c = dv(patch.control_point(i, j));
            s.p = s.p + c * (bu[i] * bv[j]);
            s.du = s.du + c * (du[i] * bv[j]);
            s.dv = s.dv + c * (bu[i] * dvv[j]);
        }
    return s;
}

struct RefHit {
    double t, u, v;
};

/// Polishes (u, v, t) with Newton on S(u, v) - o - t d = 0; nullopt unless |S - o - t d|
/// falls below 1e-12 of the patch size (a ray passing the surface at 1e-9 is no root).
inline std::optional<RefHit> ref_polish(const BezierPatch& patch, DV o, DV d, RefHit h, double size) {
    for (int it = 0; it < 40; ++it) {
        const RefSample s = ref_eval(patch, h.u, h.v);
        const DV f = s.p - o - d * h.t;
        if (dlen(f) < 1e-12 * size) return h;
        // Solve [S_u S_v -d] (du, dv, dt) = -f by Cramer's rule.
        const DV a = s.du, b = s.dv, c = d * -1.0;
        const double det = ddot(a, dcross(b, c));
        if (!(std::fabs(det) > 0)) return std::nullopt;
        const DV r = f * -1.0;
        h.u += ddot(r, dcross(b, c)) / det;
        h.v += ddot(a, dcross(r, c)) / det;
        h.t += ddot(a, dcross(b, r)) / det;
        if (!(std::fabs(h.u) < 3 && std::fabs(h.v) < 3)) return std::nullopt;
    }
    return std::nullopt;  // not converged: no root here, or the ray only nearly touches
}

/// An n x n grid of surface points in double, computed once per patch.
struct RefGrid {
    int n;
    std::vector<DV> points;  ///< (n + 1)^2, row by row (v)
    RefGrid(const BezierPatch& patch, int n_) : n(n_), points((n_ + 1) * (n_ + 1)) {
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) points[j * (n + 1) + i] = ref_eval(patch, double(i) / n, double(j) / n).p;
    }
};

/// Nearest root with t in [tmin, tmax] and (u, v) in [0, 1]^2 (1e-9 slack), from the grid's
/// triangles in double, each hit polished; nullopt when none is found.
inline std::optional<RefHit> ref_first_hit(const BezierPatch& patch, const RefGrid& grid, const Ray& ray, double tmax) {
    const DV o = dv(ray.org), d = dv(ray.dir);
    const Vec3 e = patch.bounds().extent();
    const double size = std::max({double(e.x), double(e.y), double(e.z), 1e-30});
    const int n = grid.n;
    std::vector<RefHit> candidates;
    auto tri = [&](DV a, DV b, DV c, double ua, double va, double ub, double vb, double uc, double vc) {
        // Moller-Trumbore with a little slack on the barycentrics: the polish decides.
        const DV e1 = b - a, e2 = c - a, p = dcross(d, e2);
        const double det = ddot(e1, p);
        if (det == 0) return;
        const DV s = o - a;
        const double bu = ddot(s, p) / det;
        const DV q = dcross(s, e1);
        const double bv = ddot(d, q) / det;
        const double slack = 1e-3;
        if (bu < -slack || bv < -slack || bu + bv > 1 + slack) return;
        const double t = ddot(e2, q) / det;
        candidates.push_back({t, ua + (ub - ua) * bu + (uc - ua) * bv, va + (vb - va) * bu + (vc - va) * bv});
    };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double u0 = double(i) / n, u1 = double(i + 1) / n, v0 = double(j) / n, v1 = double(j + 1) / n;
            const DV p00 = grid.points[j * (n + 1) + i], p10 = grid.points[j * (n + 1) + i + 1];
            const DV p01 = grid.points[(j + 1) * (n + 1) + i], p11 = grid.points[(j + 1) * (n + 1) + i + 1];
            tri(p00, p10, p11, u0, v0, u1, v0, u1, v1);
            tri(p00, p11, p01, u0, v0, u1, v1, u0, v1);
        }
    std::sort(candidates.begin(), candidates.end(), [](const RefHit& a, const RefHit& b) { return a.t < b.t; });
    std::optional<RefHit> best;
    for (const RefHit& c : candidates) {
        if (best && c.t > best->t + 0.1 * size) break;  // sorted: the rest are farther
        const std::optional<RefHit> h = ref_polish(patch, o, d, c, size);
        if (!h) continue;
        const double s = 1e-9;
        if (h->u < -s || h->u > 1 + s || h->v < -s || h->v > 1 + s) continue;
        if (h->t < ray.tmin || h->t > tmax) continue;
        if (!best || h->t < best->t) best = h;
    }
    return best;
}

/// Distance between the surface point at the kernel's (u, v) and the ray point at its t.
inline double hit_residual(const BezierPatch& patch, const Ray& ray, const ShapeHit& h) {
    const DV s = ref_eval(patch, h.u, h.v).p;
    return dlen(s - dv(ray.org) - dv(ray.dir) * double(h.t));
}

/// Nearest hit over several patches (the teapot); index of the patch or -1.
inline int closest_patch(const std::vector<BezierPatch>& patches, const Ray& ray, ShapeHit& best) {
    int which = -1;
    float tmax = ray.tmax;
    for (size_t i = 0; i < patches.size(); ++i) {
        ShapeHit h;
        if (patches[i].intersect(ray, tmax, h)) best = h, tmax = h.t, which = int(i);
    }
    return which;
}

}  // namespace thicket::testing
