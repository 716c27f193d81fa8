// Ray / bicubic Bezier patch intersection by recursive subdivision in ray space with Newton
// iteration where a sub-patch provably holds at most one root.
//
// The patch is moved into the ray's frame: x and y are a control point's distances from the
// ray's line along two unit vectors perpendicular to it, z its ray parameter t. A root is a
// (u, v) with x = y = 0, and the convex hull property makes the 16 transformed points' box a
// conservative test for "this sub-patch may hold a root with t in [tmin, best]" (Nishita,
// Sederberg & Kakimoto 1990 use the same frame for Bezier clipping). Sub-patches are split
// with de Casteljau at the parametric midpoint, nearer child first, until one of:
//  - the xy map of the sub-patch is one-to-one: the cones spanned by its u- and v-hodograph
//    control vectors (in xy) are pointed and no line lies in both (Sederberg's tangent-cone
//    test). Then it holds at most one root; Newton from its centre either finds it in the
//    sub-patch (done) or the sub-patch is split further. This is what makes silhouettes safe:
//    where the ray meets a fold twice the test fails and splitting goes on until the two roots
//    are in different sub-patches.
//  - its xy box is smaller than kLeafSize * patch size: the ray passes that close to every
//    point of it. Newton, else the centre, is taken as the hit.
// Every root Newton converges to (a genuine root, |x|, |y| <= tolerance) is offered, wherever
// it lies in the patch, so later boxes are culled against it. Roots up to kDomainSlack outside
// [0, 1]^2 are accepted (then clamped): a ray through the border two patches share finds a
// root in at least one of them. All of it runs in double; the sub-patch budget bounds the work
// on rays lying in the surface, where roots are not isolated.
#include "thicket/prims/bezier.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "thicket/core/error.h"
#include "thicket/core/ray_box.h"
#include "thicket/core/vec3.h"

namespace thicket {
namespace {

// The patch's arithmetic in double (Vec3d, core/vec3.h); the two helpers it adds:
inline Vec3d mid(Vec3d a, Vec3d b) { return {0.5 * (a.x + b.x), 0.5 * (a.y + b.y), 0.5 * (a.z + b.z)}; }
inline double xy_len(Vec3d a) { return std::sqrt(a.x * a.x + a.y * a.y); }  // not hypot: 10x slower

using Grid = std::array<Vec3d, 16>;  // 4 * j + i, as BezierPatch::ControlPoints

/// Cubic Bernstein basis, its first and second derivatives at t.
struct Basis {
    double b[4], db[4], ddb[4];
    explicit Basis(double t) {
        const double s = 1.0 - t;
        b[0] = s * s * s;
        b[1] = 3.0 * t * s * s;
        b[2] = 3.0 * t * t * s;
        b[3] = t * t * t;
        db[0] = -3.0 * s * s;
        db[1] = 3.0 * s * s - 6.0 * t * s;
        db[2] = 6.0 * t * s - 3.0 * t * t;
        db[3] = 3.0 * t * t;
        ddb[0] = 6.0 * s;
        ddb[1] = 6.0 * t - 12.0 * s;
        ddb[2] = 6.0 * s - 12.0 * t;
        ddb[3] = 6.0 * t;
    }
};

struct GridSample {
    Vec3d p, du, dv, duv;
};

GridSample evaluate_grid(const Grid& g, double u, double v) {
    const Basis bu(u), bv(v);
    GridSample s;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const Vec3d c = g[4 * j + i];
            s.p = s.p + c * (bu.b[i] * bv.b[j]);
            s.du = s.du + c * (bu.db[i] * bv.b[j]);
            s.dv = s.dv + c * (bu.b[i] * bv.db[j]);
            s.duv = s.duv + c * (bu.db[i] * bv.db[j]);
        }
    return s;
}

/// de Casteljau at 1/2 on the four rows (stride 1, step 4 between rows: split in u) or the
/// four columns (stride 4, step 1: split in v).
void split(const Grid& g, int stride, int step, Grid& lo, Grid& hi) {
    for (int k = 0; k < 4; ++k) {
        const int b = k * step;
        const Vec3d p0 = g[b], p1 = g[b + stride], p2 = g[b + 2 * stride], p3 = g[b + 3 * stride];
        const Vec3d p01 = mid(p0, p1), p12 = mid(p1, p2), p23 = mid(p2, p3);
        const Vec3d p012 = mid(p01, p12), p123 = mid(p12, p23), m = mid(p012, p123);
        lo[b] = p0, lo[b + stride] = p01, lo[b + 2 * stride] = p012, lo[b + 3 * stride] = m;
        hi[b] = m, hi[b + stride] = p123, hi[b + 2 * stride] = p23, hi[b + 3 * stride] = p3;
    }
}

struct Box {
    double x0, x1, y0, y1, t0, t1;
};
Box box_of(const Grid& g) {
    Box b{g[0].x, g[0].x, g[0].y, g[0].y, g[0].z, g[0].z};
    for (int k = 1; k < 16; ++k) {
        b.x0 = std::min(b.x0, g[k].x), b.x1 = std::max(b.x1, g[k].x);
        b.y0 = std::min(b.y0, g[k].y), b.y1 = std::max(b.y1, g[k].y);
        b.t0 = std::min(b.t0, g[k].z), b.t1 = std::max(b.t1, g[k].z);
    }
    return b;
}
double min_t(const Grid& g) {
    double t = g[0].z;
    for (int k = 1; k < 16; ++k) t = std::min(t, g[k].z);
    return t;
}

/// The cone (as an arc of directions: centre angle and half width) spanned by the xy parts of
/// the 12 hodograph vectors g[k + stride] - g[k] along one direction; false unless every
/// non-vanishing vector lies within 90 degrees of their sum (a pointed cone), or if all vanish.
bool hodograph_cone(const Grid& g, int stride, int step, double zero, double& centre, double& half) {
    double w[12][2];
    int n = 0;
    double rx = 0, ry = 0;
    for (int k = 0; k < 4; ++k)
        for (int m = 0; m < 3; ++m) {
            const int a = k * step + m * stride;
            const double wx = g[a + stride].x - g[a].x, wy = g[a + stride].y - g[a].y;
            if (wx * wx + wy * wy <= zero * zero) continue;  // vanishes (collapsed edge): no direction
            w[n][0] = wx, w[n][1] = wy, ++n;
            rx += wx, ry += wy;
        }
    if (n == 0 || rx * rx + ry * ry <= zero * zero) return false;
    // Angles relative to the sum through their tangents (monotone below 90 degrees).
    double lo = 0, hi = 0;
    for (int k = 0; k < n; ++k) {
        const double d = rx * w[k][0] + ry * w[k][1], c = rx * w[k][1] - ry * w[k][0];
        if (!(d > 0)) return false;
        lo = std::min(lo, c / d), hi = std::max(hi, c / d);
    }
    const double a0 = std::atan(lo), a1 = std::atan(hi);
    centre = std::atan2(ry, rx) + 0.5 * (a0 + a1);
    half = 0.5 * (a1 - a0);
    return true;
}

/// The solver of one ray against one patch.
class Solver {
public:
    static constexpr int kMaxDepth = 50;          ///< binary splits: ~2^-25 per parameter
    static constexpr int kBudget = 4096;          ///< sub-patches per ray and patch
    static constexpr double kTolerance = 1e-10;   ///< Newton residual, relative to patch size
    static constexpr double kLeafSize = 1e-7;     ///< leaf xy box, relative to patch size
    static constexpr double kDomainSlack = 1e-7;  ///< parametric slack at the patch border

    Solver(const Grid& root, double tmin, double tmax, double size, double offset, double dir_len,
           BezierQueryStats& stats)
        : root_(root), tmin_(tmin), best_t_(tmax), stats_(stats) {
        tol_ = kTolerance * size + 4e-16 * offset;
        zero_ = 1e-14 * size + 4e-16 * offset;
        leaf_ = kLeafSize * size + tol_;
        eps_t_ = tol_ / dir_len;
    }

    bool run(ShapeHit& hit) {
        visit(root_, 0.0, 1.0, 0.0, 1.0, 0);
        if (!found_) return false;
        hit.t = float(best_t_);
        hit.u = float(std::clamp(best_u_, 0.0, 1.0));
        hit.v = float(std::clamp(best_v_, 0.0, 1.0));
        // Rounding to float may step over the interval's ends that the double root respected.
        hit.t = std::clamp(hit.t, tmin_float_, tmax_float_);
        return true;
    }
    void set_float_window(float tmin, float tmax) { tmin_float_ = tmin, tmax_float_ = tmax; }

private:
    void visit(const Grid& g, double u0, double u1, double v0, double v1, int depth) {
        if (++stats_.subpatches > kBudget) {
            stats_.budget_hit = true;
            return;
        }
        const Box b = box_of(g);
        if (b.x0 > tol_ || b.x1 < -tol_ || b.y0 > tol_ || b.y1 < -tol_) return;
        if (b.t1 < tmin_ - eps_t_ || b.t0 > best_t_ + (found_ ? 0.0 : eps_t_)) return;
        if (!straddles_ray(g)) return;

        const bool leaf = depth >= kMaxDepth || std::max(b.x1 - b.x0, b.y1 - b.y0) <= leaf_;
        if (leaf || injective(g)) {
            double u = 0.5 * (u0 + u1), v = 0.5 * (v0 + v1), t = 0.0;
            ++stats_.newton_runs;
            if (newton(u, v, t)) {
                offer(u, v, t);
                const double su = kDomainSlack + 1e-9 * (u1 - u0), sv = kDomainSlack + 1e-9 * (v1 - v0);
                if (u >= u0 - su && u <= u1 + su && v >= v0 - sv && v <= v1 + sv) return;
            }
            if (leaf) {  // the ray passes within leaf_ of every point of this sub-patch
                const double uc = 0.5 * (u0 + u1), vc = 0.5 * (v0 + v1);
                offer(uc, vc, evaluate_grid(root_, uc, vc).p.z);
                return;
            }
        }

        // Split across the direction along which the control polygon is longer in xy.
        double len_u = 0, len_v = 0;
        for (int k = 0; k < 4; ++k) {
            double lu = 0, lv = 0;
            for (int m = 0; m < 3; ++m) {
                lu += xy_len(g[4 * k + m + 1] - g[4 * k + m]);
                lv += xy_len(g[4 * (m + 1) + k] - g[4 * m + k]);
            }
            len_u = std::max(len_u, lu), len_v = std::max(len_v, lv);
        }
        Grid lo, hi;
        const bool along_u = len_u >= len_v;
        if (along_u)
            split(g, 1, 4, lo, hi);
        else
            split(g, 4, 1, lo, hi);
        const double um = 0.5 * (u0 + u1), vm = 0.5 * (v0 + v1);
        const bool lo_first = min_t(lo) <= min_t(hi);
        for (int c = 0; c < 2; ++c) {
            const bool take_lo = (c == 0) == lo_first;
            if (along_u)
                visit(take_lo ? lo : hi, take_lo ? u0 : um, take_lo ? um : u1, v0, v1, depth + 1);
            else
                visit(take_lo ? lo : hi, u0, u1, take_lo ? v0 : vm, take_lo ? vm : v1, depth + 1);
        }
    }

    /// The axis-aligned xy box is loose where the sub-patch projects to a thin tilted sliver
    /// (a ray grazing the surface: its image is squashed by the sine of the angle), and then
    /// every sub-patch along the ray for a long way would survive it. Slabs across the
    /// sub-patch's own u and v chords (Bezier clipping's "fat lines") hug the sliver.
    bool straddles_ray(const Grid& g) const {
        const double chords[2][2] = {{g[3].x - g[0].x + g[15].x - g[12].x, g[3].y - g[0].y + g[15].y - g[12].y},
                                     {g[12].x - g[0].x + g[15].x - g[3].x, g[12].y - g[0].y + g[15].y - g[3].y}};
        for (const auto& c : chords) {
            const double len = std::sqrt(c[0] * c[0] + c[1] * c[1]);
            if (!(len > zero_)) continue;
            const double nx = -c[1] / len, ny = c[0] / len;
            double lo = nx * g[0].x + ny * g[0].y, hi = lo;
            for (int k = 1; k < 16; ++k) {
                const double d = nx * g[k].x + ny * g[k].y;
                lo = std::min(lo, d), hi = std::max(hi, d);
            }
            if (lo > tol_ || hi < -tol_) return false;
        }
        return true;
    }

    /// Whether the sub-patch's xy map is one-to-one (hence holds at most one root): for two
    /// parameter points, P(b) - P(a) = du * (mean of P_u) + dv * (mean of P_v), the means lie in
    /// the hodograph cones, and it can vanish only if some line lies in both double cones.
    bool injective(const Grid& g) const {
        double cu, hu, cv, hv;
        if (!hodograph_cone(g, 1, 4, zero_, cu, hu) || !hodograph_cone(g, 4, 1, zero_, cv, hv)) return false;
        const double apart = std::fabs(std::remainder(cu - cv, std::numbers::pi));  // distance of lines, in [0, pi/2]
        return apart > hu + hv + 1e-9;
    }

    /// Newton on (x, y)(u, v) = 0 over the whole patch; true with t when it converges.
    bool newton(double& u, double& v, double& t) const {
        for (int it = 0; it < 24; ++it) {
            const GridSample s = evaluate_grid(root_, u, v);
            if (std::fabs(s.p.x) <= tol_ && std::fabs(s.p.y) <= tol_) {
                t = s.p.z;
                return true;
            }
            const double det = s.du.x * s.dv.y - s.du.y * s.dv.x;
            if (!(std::fabs(det) > 0.0)) return false;
            const double du = (s.p.y * s.dv.x - s.p.x * s.dv.y) / det;
            const double dv = (s.p.x * s.du.y - s.p.y * s.du.x) / det;
            u += du, v += dv;
            if (!(u > -0.5 && u < 1.5 && v > -0.5 && v < 1.5)) return false;  // NaN fails too
        }
        return false;
    }

    void offer(double u, double v, double t) {
        if (!(u >= -kDomainSlack && u <= 1.0 + kDomainSlack && v >= -kDomainSlack && v <= 1.0 + kDomainSlack))
            return;
        // Within rounding of the interval's ends counts (run() clamps): a root exactly at
        // tmin or tmax is computed a few ulps either side.
        if (!(t >= tmin_ - eps_t_ && (found_ ? t < best_t_ : t <= best_t_ + eps_t_))) return;
        found_ = true;
        best_t_ = t, best_u_ = u, best_v_ = v;
    }

    const Grid& root_;
    double tmin_, best_t_;
    float tmin_float_ = 0.0f, tmax_float_ = kInfinity;
    double best_u_ = 0, best_v_ = 0;
    bool found_ = false;
    double tol_, zero_, leaf_, eps_t_;
    BezierQueryStats& stats_;
};

}  // namespace

BezierPatch::BezierPatch(const ControlPoints& cp) : cp_(cp) {
    Aabb b;
    for (int k = 0; k < 16; ++k) {
        const Vec3 c = cp[k];
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
            throw Error("Bezier patch: control point " + std::to_string(k) + " has a non-finite coordinate");
        b.grow(c);
    }
    bounds_ = b;
}

bool intersect_counted(const BezierPatch& patch, const Ray& ray, float tmax, ShapeHit& hit, BezierQueryStats& stats) {
    if (!(ray.tmin <= tmax)) return false;
    const Aabb box = patch.bounds();
    if (ray_box_entry(RayBoxQuery(ray), box, ray.tmin, tmax) == kInfinity) return false;

    const Vec3d o = Vec3d(ray.org), d = Vec3d(ray.dir);
    const double len2 = dot(d, d), len = std::sqrt(len2);
    if (!(len2 > 0.0) || !std::isfinite(len2)) return false;
    const Vec3d n = d * (1.0 / len);
    // Two unit vectors perpendicular to the ray, from its largest components (no cancellation).
    const Vec3d e1 = std::fabs(n.x) > std::fabs(n.y) ? Vec3d{-n.z, 0.0, n.x} * (1.0 / std::sqrt(n.x * n.x + n.z * n.z))
                                                  : Vec3d{0.0, n.z, -n.y} * (1.0 / std::sqrt(n.y * n.y + n.z * n.z));
    const Vec3d e2 = cross(n, e1);
    Grid g;
    for (int k = 0; k < 16; ++k) {
        const Vec3d w = Vec3d(patch.control_points()[k]) - o;
        g[k] = {dot(e1, w), dot(e2, w), dot(d, w) / len2};
    }
    const Vec3 ext = box.extent();
    const double size = std::max({double(ext.x), double(ext.y), double(ext.z)});
    if (!(size > 0.0)) return false;  // all control points coincide: no area
    const double offset = length(Vec3d(box.center()) - o) + size;
    // Roots that round to the float window's ends count: the window in double reaches half an ulp
    // beyond them (a structure passes its closest hit so far, a float, as tmax).
    const double tmin_d = ray.tmin > 0.0f ? 0.5 * (double(ray.tmin) + double(std::nextafter(ray.tmin, 0.0f))) : double(ray.tmin);
    const double tmax_d = std::isfinite(tmax) ? 0.5 * (double(tmax) + double(std::nextafter(tmax, kInfinity))) : double(tmax);
    Solver solver(g, tmin_d, tmax_d, size, offset, len, stats);
    solver.set_float_window(ray.tmin, tmax);
    return solver.run(hit);
}

bool BezierPatch::intersect(const Ray& ray, float tmax, ShapeHit& hit) const {
    BezierQueryStats stats;
    return intersect_counted(*this, ray, tmax, hit, stats);
}

BezierSample BezierPatch::evaluate(float u, float v) const {
    Grid g;
    for (int k = 0; k < 16; ++k) g[k] = Vec3d(cp_[k]);
    const GridSample s = evaluate_grid(g, u, v);
    auto f = [](Vec3d a) { return Vec3(float(a.x), float(a.y), float(a.z)); };
    return {f(s.p), f(s.du), f(s.dv)};
}

Vec3 BezierPatch::normal(Vec3, float uf, float vf) const {
    Grid g;
    for (int k = 0; k < 16; ++k) g[k] = Vec3d(cp_[k]);
    const double u = std::clamp(double(uf), 0.0, 1.0), v = std::clamp(double(vf), 0.0, 1.0);
    const Vec3 ext = bounds_.extent();
    const double size = std::max({double(ext.x), double(ext.y), double(ext.z)});
    const double tiny = 1e-10 * size * size;  // |n| below this is rounding noise
    auto unit = [](Vec3d a) {
        const double l = length(a);
        return Vec3(float(a.x / l), float(a.y / l), float(a.z / l));
    };
    const GridSample s = evaluate_grid(g, u, v);
    Vec3d n = cross(s.du, s.dv);
    if (length(n) > tiny) return unit(n);
    // A collapsed edge: along it one partial vanishes, and near it that partial grows linearly
    // with the distance from the edge, so the normal's limit is the mixed partial crossed with
    // the other one, signed by the side the patch lies on.
    if (length(s.du) <= length(s.dv))
        n = cross(s.duv, s.dv) * (v < 0.5 ? 1.0 : -1.0);
    else
        n = cross(s.du, s.duv) * (u < 0.5 ? 1.0 : -1.0);
    if (length(n) > tiny) return unit(n);
    // Both partials vanish, or are parallel (a cusp): the nearest defined normal inside.
    for (double eta : {1e-6, 1e-4, 1e-2, 1e-1, 0.5}) {
        const GridSample q = evaluate_grid(g, u + eta * (0.5 - u), v + eta * (0.5 - v));
        n = cross(q.du, q.dv);
        if (length(n) > tiny) return unit(n);
    }
    return {0.0f, 0.0f, 1.0f};  // no area anywhere: every direction is as good
}

}  // namespace thicket
