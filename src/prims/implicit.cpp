// Root finding for the implicit-surface kernels: interval root isolation (the default) and
// sphere tracing, both over a surface's line evaluator (implicit.h).
#include "thicket/prims/implicit.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <type_traits>
#include <utility>

#include "thicket/core/error.h"
#include "thicket/core/hash.h"

namespace thicket {

// ---- line forms and surface bounds -------------------------------------------------------

LineDistance2::LineDistance2(const Line3d& l, const Vec3d& c) : d(l.d) {
    Interval aa(0.0), bb(0.0), cc(0.0);
    for (int k = 0; k < 3; ++k) {
        oc[k] = l.o[k] - c[k];
        const Interval o = Interval(l.o[k]) - c[k];  // the rounding of oc, enclosed
        aa += sqr(Interval(l.d[k]));
        bb += o * l.d[k];
        cc += sqr(o);
    }
    a = aa;
    tstar = -bb / aa;
    // |o + t d|^2 = a (t - t*)^2 + (c - b^2 / a); the exact h^2 is a squared distance, so >= 0.
    h2 = max0(cc - sqr(bb) / aa);
}

Box3d TangleCube::box() const {
    const double r = std::sqrt(0.5 * (5.0 + std::sqrt(25.0 + 4.0 * (12.5 - kConstant)))) + 1e-3;
    return {{-r, -r, -r}, {r, r, r}};
}

Box3d BlobSum::box() const {
    Box3d b{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
    for (const Blob& blob : blobs)
        for (int k = 0; k < 3; ++k) {
            b.lo[k] = std::min(b.lo[k], blob.center[k] - blob.radius);
            b.hi[k] = std::max(b.hi[k], blob.center[k] + blob.radius);
        }
    return b;
}

double BlobSum::lipschitz_bound() const {
    double l = 0.0;
    for (const Blob& b : blobs) l += b.weight * 8.0 / (3.0 * std::sqrt(3.0) * b.radius);
    return l;
}

// ---- blobs along a line ------------------------------------------------------------------

BlobsLineEval::BlobsLineEval(const BlobSum& sum, const Line3d& line) : threshold_(sum.threshold) {
    for (const Blob& b : sum.blobs) {
        LineDistance2 dist(line, b.center);
        const double r2 = b.radius * b.radius;
        // A blob the line passes farther than R from contributes 0 everywhere on it.
        if (dist.h2.lo > r2) continue;
        const Term term{dist, 1.0 / r2, b.weight};
        if (count_ < kInline) {
            inline_[count_] = term;
        } else {
            if (overflow_.empty()) overflow_.assign(inline_.begin(), inline_.end());
            overflow_.push_back(term);
        }
        ++count_;
    }
}

Interval BlobsLineEval::value(const Interval& t) const {
    Interval sum(0.0);
    const Term* terms = this->terms();
    for (size_t i = 0; i < count_; ++i) {
        const Term& term = terms[i];
        sum += term.weight * sqr(max0(1.0 - term.dist.eval(t) * term.inv_r2));
    }
    return threshold_ - sum;
}

Interval BlobsLineEval::slope(const Interval& t) const {
    // d/dt [-w max(0, 1 - s/R^2)^2] = w 4 max(0, 1 - s/R^2) a (t - t*) / R^2 for s = a (t - t*)^2 + h^2
    // (both sides 0 where the clamp is active).
    Interval sum(0.0);
    const Term* terms = this->terms();
    for (size_t i = 0; i < count_; ++i) {
        const Term& term = terms[i];
        const Interval m = max0(1.0 - term.dist.eval(t) * term.inv_r2);
        sum += (4.0 * term.weight * term.inv_r2) * m * (term.dist.a * (t - term.dist.tstar));
    }
    return sum;
}

double BlobsLineEval::value(double t) const {
    double sum = 0.0;
    const Term* terms = this->terms();
    for (size_t i = 0; i < count_; ++i) {
        const Term& term = terms[i];
        sum += term.weight * sqr(max0(1.0 - term.dist.eval(t) * term.inv_r2));
    }
    return threshold_ - sum;
}

namespace {

template <class S>
struct LineEvalFor {
    using type = GenericLineEval<S>;
};
template <>
struct LineEvalFor<BlobSum> {
    using type = BlobsLineEval;
};

// ---- root finders ------------------------------------------------------------------------

/// Bisection on [lo, hi] where f(lo) has sign `lo_negative` and f(hi) the other sign, down to
/// `tol` or to the resolution of double. Returns the midpoint of the last bracket.
template <class E>
double refine_root(const E& e, double lo, double hi, bool lo_negative, double tol) {
    for (int i = 0; i < 200; ++i) {
        const double m = 0.5 * (lo + hi);
        if (!(hi - lo > tol) || m <= lo || m >= hi) break;
        const double fm = e.value(m);
        if (fm == 0.0) return m;
        ((fm < 0.0) == lo_negative ? lo : hi) = m;
    }
    return 0.5 * (lo + hi);
}

/// Interval root isolation (Mitchell 1990, Knoll et al. 2007): the first t in [a, b] where f
/// along the line vanishes. Depth-first over t-intervals, left half first, so the first root
/// accepted is the first in t order. For an interval T:
///   - F = f(T) by the natural extension, narrowed by the mean-value form f(m) + f'(T)(T - m);
///     0 not in F proves there is no root: discard.
///   - 0 not in f'(T): f is strictly monotone on T, so it has a root iff the endpoint values
///     (as point intervals, so their signs are certain) differ in sign; refine it by bisection.
///   - otherwise split, until T is narrower than tol; then a sign change between the endpoints
///     is refined, and without one the interval is a tangential root candidate: f and f' may
///     both vanish in it, and it is accepted at its midpoint (Knoll's rule for double roots).
/// Never misses a root: only intervals proven root-free are discarded. May accept a near miss
/// where min |f| on T is below the mean-value form's overestimate, ~ |f''| tol^2 / 2.
/// Spans beginning beyond `limit` are not searched (a root there would be rejected anyway), but
/// the spans are the halvings of [a, b] whatever the limit, so the root found does not depend on it.
/// `budget`: spans split at most (the work bound; see span_budget).
template <class E>
std::optional<double> isolate_first_root(const E& e, double a, double b, double tol, double limit, long budget) {
    struct Span {
        double t0, t1;
    };
    // Depth-first with halving: at most log2((b - a) / tol) + 1 spans are pending; the caller
    // keeps (b - a) / tol below 2^60.
    Span stack[96];
    int n = 0;
    stack[n++] = {a, b};
    const double refine_tol = 1e-3 * tol;
    // A budget that only a function flat to within rounding over a long stretch can exhaust; the
    // pending interval then may contain a root, and is reported (a hit is the safe side).
    while (n > 0) {
        const Span s = stack[--n];
        if (s.t0 > limit) return std::nullopt;  // the top span is the leftmost pending one
        const Interval t(s.t0, s.t1);
        Interval f = e.value(t);
        if (!contains_zero(f)) continue;
        const Interval slope = e.slope(t);
        const double m = t.mid();
        f = intersect(f, e.value(Interval(m)) + slope * (t - m));
        if (!contains_zero(f)) continue;
        const bool monotone = !contains_zero(slope);
        if (!monotone && s.t1 - s.t0 > tol && --budget > 0 && n + 2 <= 96) {
            stack[n++] = {m, s.t1};
            stack[n++] = {s.t0, m};
            continue;
        }
        const Interval f0 = e.value(Interval(s.t0)), f1 = e.value(Interval(s.t1));
        if (!contains_zero(f0) && !contains_zero(f1)) {
            const bool neg0 = f0.hi < 0.0, neg1 = f1.hi < 0.0;
            if (neg0 != neg1) return refine_root(e, s.t0, s.t1, neg0, refine_tol);
            if (monotone) continue;  // no sign change and monotone: no root
            return m;                // tangential candidate below tol
        }
        // An endpoint value is zero to within rounding: that endpoint is a root.
        return contains_zero(f0) ? s.t0 : s.t1;
    }
    return std::nullopt;
}

/// Sphere tracing with a Lipschitz bound (Hart 1996): |f(t + dt)| >= |f(t)| - lip_t |dt|, so a
/// step of |f| / lip_t cannot pass a root. Steps are at least min_dt (else the march would crawl
/// towards a tangency forever); a sign change between two steps is refined by bisection. Two
/// roots closer than min_dt (a grazing ray) can be stepped over; max_steps bounds the work. The
/// march gives up beyond `limit`, but its steps do not depend on it.
template <class E>
std::optional<double> sphere_trace_first_root(const E& e, double a, double b, double lip_t, double min_dt,
                                              int max_steps, double refine_tol, double limit) {
    double t = a, f = e.value(a);
    if (f == 0.0) return a;
    const bool negative = f < 0.0;
    for (int i = 0; i < max_steps && t <= limit; ++i) {
        double tn = t + std::max(std::fabs(f) / lip_t, min_dt);
        const bool last = !(tn < b);
        if (last) tn = b;
        const double fn = e.value(tn);
        if (fn == 0.0) return tn;
        if ((fn < 0.0) != negative) return refine_root(e, t, tn, negative, refine_tol);
        if (last) return std::nullopt;
        t = tn;
        f = fn;
    }
    return std::nullopt;
}

void check_surface(const TangleCube&) {}
void check_surface(const BarthSextic& s) {
    if (!(s.clip > 0.0) || !std::isfinite(s.clip))
        throw Error("implicit barth-sextic: clip must be positive and finite, got " + format_number(s.clip));
}
void check_surface(const BlobSum& s) {
    if (s.blobs.empty()) throw Error("blobs: at least one blob is needed");
    if (s.blobs.size() > kMaxBlobs)
        throw Error("blobs: " + std::to_string(s.blobs.size()) + " blobs, more than " + std::to_string(kMaxBlobs) +
                    " (the bound that keeps the work per ray bounded)");
    if (!(s.threshold > 0.0) || !std::isfinite(s.threshold))
        throw Error("blobs: threshold must be positive and finite, got " + format_number(s.threshold));
    for (size_t i = 0; i < s.blobs.size(); ++i) {
        const Blob& b = s.blobs[i];
        const std::string which = "blobs: blob " + std::to_string(i) + ": ";
        for (int k = 0; k < 3; ++k)
            if (!std::isfinite(b.center[k]))
                throw Error(which + "center coordinate " + format_number(b.center[k]) + " is not finite");
        if (!(b.radius > 0.0) || !std::isfinite(b.radius))
            throw Error(which + "radius must be positive and finite, got " + format_number(b.radius));
        if (!(b.weight > 0.0) || !std::isfinite(b.weight))
            throw Error(which + "weight must be positive and finite, got " + format_number(b.weight));
    }
}

double lipschitz_of(const TangleCube& s, const Box3d& box) { return lipschitz_over_box(s, box, 16); }
double lipschitz_of(const BarthSextic& s, const Box3d& box) { return lipschitz_over_box(s, box, 16); }
double lipschitz_of(const BlobSum& s, const Box3d&) { return s.lipschitz_bound(); }

/// Terms of f that one evaluation along a ray may sum: what the work per step scales with.
int64_t terms_of(const TangleCube&) { return 1; }
int64_t terms_of(const BarthSextic&) { return 1; }
int64_t terms_of(const BlobSum& s) { return int64_t(s.blobs.size()); }

/// The interval method's span budget: 2^20 spans for a surface of a few terms (only a function
/// flat to within rounding over a long stretch exhausts it), fewer for many blobs so that the
/// worst ray stays near kMaxImplicitWorkPerRay term evaluations, never below 2^14.
long span_budget(int64_t terms) {
    return long(std::clamp<int64_t>(kMaxImplicitWorkPerRay / terms, int64_t(1) << 14, int64_t(1) << 20));
}

uint64_t hash_surface(const TangleCube&, uint64_t h) { return h; }
uint64_t hash_surface(const BarthSextic& s, uint64_t h) { return fnv1a(&s.clip, sizeof s.clip, h); }
uint64_t hash_surface(const BlobSum& s, uint64_t h) {
    static_assert(sizeof(Blob) == 5 * sizeof(double), "Blob is hashed as its bytes");
    h = fnv1a(&s.threshold, sizeof s.threshold, h);
    return fnv1a(s.blobs.data(), s.blobs.size() * sizeof(Blob), h);
}

}  // namespace

// ---- the kernel --------------------------------------------------------------------------

ImplicitMethod parse_implicit_method(const std::string& name) {
    if (name == "interval") return ImplicitMethod::interval;
    if (name == "sphere-tracing") return ImplicitMethod::sphere_tracing;
    throw Error("implicit: unknown method '" + name + "' (allowed: interval, sphere-tracing)");
}

const char* to_string(ImplicitMethod m) { return m == ImplicitMethod::interval ? "interval" : "sphere-tracing"; }

template <class S>
ImplicitKernel<S>::ImplicitKernel(S surface, const ImplicitOptions& options)
    : surface_(std::move(surface)), options_(options) {
    check_surface(surface_);
    if (!is_finite(options.center)) throw Error("implicit: center must be finite");
    if (!(options.scale > 0.0f) || !std::isfinite(options.scale))
        throw Error("implicit: scale must be positive and finite, got " + format_number(options.scale));
    if (!(options.epsilon >= 0.0) || !std::isfinite(options.epsilon))
        throw Error("implicit: epsilon must be positive and finite (or 0 for the default), got " +
                    format_number(options.epsilon));
    if (options.max_steps < 1)
        throw Error("implicit: max-steps must be at least 1, got " + std::to_string(options.max_steps));
    // Each sphere-tracing step evaluates every term of f (every blob the ray passes near).
    if (options.method == ImplicitMethod::sphere_tracing &&
        int64_t(options.max_steps) * terms_of(surface_) > kMaxImplicitWorkPerRay)
        throw Error("implicit: max-steps x terms = " + std::to_string(options.max_steps) + " x " +
                    std::to_string(terms_of(surface_)) + " = " +
                    std::to_string(int64_t(options.max_steps) * terms_of(surface_)) + " exceeds " +
                    std::to_string(kMaxImplicitWorkPerRay) + ", the bound on the work per ray");
    box_ = surface_.box();
    double diag2 = 0.0;
    Vec3d lo, hi;
    for (int k = 0; k < 3; ++k) {
        diag2 += sqr(box_.hi[k] - box_.lo[k]);
        lo[k] = double(options.center[k]) + double(options.scale) * box_.lo[k];
        hi[k] = double(options.center[k]) + double(options.scale) * box_.hi[k];
    }
    // The world box is computed in double and then rounded outward: it encloses the object box
    // up to double rounding, far below the slab test's slack.
    bounds_ = outward_box(lo, hi);
    if (!is_finite(bounds_.min) || !is_finite(bounds_.max))
        throw Error("implicit: the shape's bounds overflow float (center " + format_number(options.center.x) + ", scale " +
                    format_number(options.scale) + ")");
    epsilon_ = options.epsilon > 0.0 ? options.epsilon : 1e-6 * std::sqrt(diag2);
    lipschitz_ = lipschitz_of(surface_, box_);
}

template <class S>
bool ImplicitKernel<S>::object_segment(const Ray& ray, float tmax, Line3d& line, double& t0, double& t1) const {
    const double inv_scale = 1.0 / double(options_.scale);
    t0 = ray.tmin;
    t1 = tmax;
    for (int k = 0; k < 3; ++k) {
        line.o[k] = (double(ray.org[k]) - double(options_.center[k])) * inv_scale;
        line.d[k] = double(ray.dir[k]) * inv_scale;
        if (line.d[k] == 0.0) {
            if (!(line.o[k] >= box_.lo[k] && line.o[k] <= box_.hi[k])) return false;
            continue;
        }
        double ta = (box_.lo[k] - line.o[k]) / line.d[k], tb = (box_.hi[k] - line.o[k]) / line.d[k];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;  // false for NaN too
}

template <class S>
bool ImplicitKernel<S>::intersect(const Ray& ray, float tmax, ShapeHit& hit) const {
    // The search runs over the whole segment inside the box, not cut at tmax: a structure calls
    // this with its current closest hit as tmax, and must get the same root as brute force.
    Line3d line;
    double t0, t1;
    // Roots up to the next float count: they round to tmax itself.
    const double limit = double(std::nextafter(tmax, kInfinity));
    if (!(ray.tmin <= tmax) || !object_segment(ray, kInfinity, line, t0, t1) || t0 > limit) return false;
    const double dlen = std::sqrt(sqr(line.d[0]) + sqr(line.d[1]) + sqr(line.d[2]));
    if (!(dlen > 0.0) || !std::isfinite(dlen) || !std::isfinite(t0) || !std::isfinite(t1)) return false;
    const typename LineEvalFor<S>::type eval(surface_, line);
    const double tol = std::max(epsilon_ / dlen, (t1 - t0) * 0x1p-60);
    std::optional<double> root;
    if (options_.method == ImplicitMethod::interval)
        root = isolate_first_root(eval, t0, t1, tol, limit, span_budget(terms_of(surface_)));
    else
        root = sphere_trace_first_root(eval, t0, t1, lipschitz_ * dlen, tol, options_.max_steps, 1e-3 * tol, limit);
    // ray.tmin <= root, a float, so the rounded root stays at or above it.
    if (!root || !(float(*root) <= tmax)) return false;
    hit = {float(*root), 0.0f, 0.0f};
    return true;
}

template <class S>
Vec3 ImplicitKernel<S>::normal(Vec3 p, float, float) const {
    Vec3d q;
    for (int k = 0; k < 3; ++k) q[k] = (double(p[k]) - double(options_.center[k])) / double(options_.scale);
    const auto g = surface_.gradient(q[0], q[1], q[2]);
    double len = std::sqrt(sqr(g[0]) + sqr(g[1]) + sqr(g[2]));
    if (len > 0.0 && std::isfinite(len)) return Vec3(float(g[0] / len), float(g[1] / len), float(g[2] / len));
    Vec3d r;
    for (int k = 0; k < 3; ++k) r[k] = q[k] - 0.5 * (box_.lo[k] + box_.hi[k]);
    len = std::sqrt(sqr(r[0]) + sqr(r[1]) + sqr(r[2]));
    if (len > 0.0 && std::isfinite(len)) return Vec3(float(r[0] / len), float(r[1] / len), float(r[2] / len));
    return Vec3(0.0f, 0.0f, 1.0f);
}

template <class S>
uint64_t ImplicitKernel<S>::hash(uint64_t h) const {
    h = hash_surface(surface_, h);
    const int method = int(options_.method);
    h = fnv1a(&options_.center, sizeof options_.center, h);
    h = fnv1a(&options_.scale, sizeof options_.scale, h);
    h = fnv1a(&method, sizeof method, h);
    h = fnv1a(&options_.epsilon, sizeof options_.epsilon, h);
    return fnv1a(&options_.max_steps, sizeof options_.max_steps, h);
}

template class ImplicitKernel<TangleCube>;
template class ImplicitKernel<BarthSextic>;
template class ImplicitKernel<BlobSum>;

Implicit::Implicit(const std::string& surface, const ImplicitOptions& options, double clip)
    : kernel_(surface == "tangle-cube" ? Kernel(ImplicitKernel<TangleCube>(TangleCube{}, options))
              : surface == "barth-sextic"
                  ? Kernel(ImplicitKernel<BarthSextic>(BarthSextic{clip}, options))
                  : throw Error("implicit: unknown surface '" + surface + "' (allowed: tangle-cube, barth-sextic)")) {}

uint64_t Implicit::hash(uint64_t seed) const {
    const uint64_t which = kernel_.index();
    seed = fnv1a(&which, sizeof which, seed);
    return std::visit([seed](const auto& k) { return k.hash(seed); }, kernel_);
}

}  // namespace thicket
