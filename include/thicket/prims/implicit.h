#pragma once
/// Algebraic implicit surfaces f(x, y, z) = 0 as shape kernels (shape.h), intersected either by
/// interval-arithmetic root isolation (Mitchell, GI '90; Knoll et al., RT '07), which never
/// misses a root, or by sphere tracing with a Lipschitz bound (Hart 1996). The surfaces:
///   TangleCube   x^4 - 5x^2 + y^4 - 5y^2 + z^4 - 5z^2 + 11.8 = 0
///   BarthSextic  4(p^2x^2 - y^2)(p^2y^2 - z^2)(p^2z^2 - x^2) - (1 + 2p)(x^2 + y^2 + z^2 - 1)^2 = 0,
///                p the golden ratio, clipped to a cube (the surface itself is unbounded)
///   BlobSum      threshold - sum_i w_i max(0, 1 - |x - c_i|^2 / R_i^2)^2 = 0 (polynomial metaballs)
/// Every f is negative inside, so its gradient is the outward normal. The kernels: Implicit
/// (JSON type "implicit": tangle cube, Barth sextic) and Blobs ("blobs"), both over
/// ImplicitKernel<S>. docs/implicit-fractal.md states the tolerances and failure modes.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"
#include "thicket/prims/interval.h"
#include "thicket/prims/shape.h"
#include "thicket/prims/shape_util.h"

namespace thicket {

/// The kernels' one double 3-vector (shape_util.h), under the name the implicit code uses.
using Vec3d = Vec3d;

/// An axis-aligned box in an implicit surface's own (object) coordinates.
struct Box3d {
    Vec3d lo{}, hi{};
};

/// A line o + t d in object coordinates: what the root finders evaluate surfaces along.
struct Line3d {
    Vec3d o{}, d{};
    Vec3d at(double t) const { return {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]}; }
};

/// The enclosure of a line's points over a parameter interval, axis by axis (exact up to
/// the widening of the two operations).
inline std::array<Interval, 3> line_box(const Line3d& l, const Interval& t) {
    return {Interval(l.o[0]) + t * l.d[0], Interval(l.o[1]) + t * l.d[1], Interval(l.o[2]) + t * l.d[2]};
}

/// |o + t d - c|^2 along a line in the form a (t - t*)^2 + h^2, whose interval extension is the
/// exact range (one occurrence of t, under the even-power rule) instead of the sum of three
/// independently bounded squares. Coefficients are intervals, so the form stays an enclosure.
struct LineDistance2 {
    Interval a, tstar, h2;
    Vec3d oc{}, d{};  // for point evaluation

    LineDistance2() = default;
    LineDistance2(const Line3d& l, const Vec3d& c);
    Interval eval(const Interval& t) const { return a * sqr(t - tstar) + h2; }
    double eval(double t) const {
        const double x = oc[0] + t * d[0], y = oc[1] + t * d[1], z = oc[2] + t * d[2];
        return x * x + y * y + z * z;
    }
};

// ---- surfaces ----------------------------------------------------------------------------
// Each surface offers value() and gradient() as templates over double and Interval, box()
// (conservative object-space bounds of the part of the surface that is rendered) and a line
// evaluator (LineEval) that the root finders use: value and slope d/dt along a line, as
// intervals over a t-interval and as a double at a point.

/// x^4 - 5x^2 + y^4 - 5y^2 + z^4 - 5z^2 + 11.8 = 0, written per axis as (x^2 - 2.5)^2 - 6.25 so
/// that the interval extension of each axis term is its exact range.
struct TangleCube {
    static constexpr double kConstant = 11.8;

    template <class T>
    static T axis_term(const T& x) { return sqr(sqr(x) - 2.5) - 6.25; }
    template <class T>
    static T axis_slope(const T& x) { return 4.0 * x * (sqr(x) - 2.5); }

    template <class T>
    T value(const T& x, const T& y, const T& z) const {
        return axis_term(x) + axis_term(y) + axis_term(z) + kConstant;
    }
    template <class T>
    std::array<T, 3> gradient(const T& x, const T& y, const T& z) const {
        return {axis_slope(x), axis_slope(y), axis_slope(z)};
    }
    /// Each axis term is >= -6.25, so on the surface x^4 - 5x^2 <= 12.5 - 11.8 = 0.7, which bounds
    /// |x| by sqrt((5 + sqrt(27.8)) / 2) = 2.26633; the box adds 1e-3.
    Box3d box() const;
};

/// Barth's sextic (65 ordinary double points), restricted to the cube |x|, |y|, |z| <= clip.
struct BarthSextic {
    static constexpr double kPhi = 1.6180339887498948482;  // golden ratio
    static constexpr double kPhi2 = kPhi * kPhi;
    double clip = 1.0;  ///< half-size of the clipping cube, object units

    template <class T>
    T value(const T& x, const T& y, const T& z) const {
        const T x2 = sqr(x), y2 = sqr(y), z2 = sqr(z);
        const T a = kPhi2 * x2 - y2, b = kPhi2 * y2 - z2, c = kPhi2 * z2 - x2;
        return 4.0 * (a * b * c) - (1.0 + 2.0 * kPhi) * sqr(x2 + y2 + z2 - 1.0);
    }
    template <class T>
    std::array<T, 3> gradient(const T& x, const T& y, const T& z) const {
        const T x2 = sqr(x), y2 = sqr(y), z2 = sqr(z);
        const T a = kPhi2 * x2 - y2, b = kPhi2 * y2 - z2, c = kPhi2 * z2 - x2;
        const T q = (4.0 * (1.0 + 2.0 * kPhi)) * (x2 + y2 + z2 - 1.0);
        return {x * (8.0 * (kPhi2 * (b * c) - a * b) - q), y * (8.0 * (kPhi2 * (a * c) - b * c) - q),
                z * (8.0 * (kPhi2 * (a * b) - a * c) - q)};
    }
    Box3d box() const { return {{-clip, -clip, -clip}, {clip, clip, clip}}; }
};

/// One metaball: weight w, support radius R around a center.
struct Blob {
    Vec3d center{};
    double radius = 1.0;
    double weight = 1.0;
};

/// threshold - sum_i w_i max(0, 1 - r_i^2 / R_i^2)^2 = 0. The kernel is C^1 (value and slope
/// vanish at r = R) and piecewise polynomial; the clamp max(0, .) is monotone, so its interval
/// extension is exact. A single blob is the sphere of radius R sqrt(1 - sqrt(threshold / w)).
struct BlobSum {
    std::vector<Blob> blobs;
    double threshold = 0.5;

    template <class T>
    T value(const T& x, const T& y, const T& z) const {
        T sum(0.0);
        for (const Blob& b : blobs) {
            const T r2 = sqr(x - b.center[0]) + sqr(y - b.center[1]) + sqr(z - b.center[2]);
            sum += b.weight * sqr(max0(1.0 - r2 * (1.0 / (b.radius * b.radius))));
        }
        return threshold - sum;
    }
    template <class T>
    std::array<T, 3> gradient(const T& x, const T& y, const T& z) const {
        std::array<T, 3> g{T(0.0), T(0.0), T(0.0)};
        for (const Blob& b : blobs) {
            const double inv_r2 = 1.0 / (b.radius * b.radius);
            const T dx = x - b.center[0], dy = y - b.center[1], dz = z - b.center[2];
            const T m = max0(1.0 - (sqr(dx) + sqr(dy) + sqr(dz)) * inv_r2);
            const T k = (4.0 * b.weight * inv_r2) * m;
            g[0] += k * dx;
            g[1] += k * dy;
            g[2] += k * dz;
        }
        return g;
    }
    /// The union of the supports (outside every support f = threshold > 0).
    Box3d box() const;
    /// sup |grad f| <= sum_i w_i max_r 4 (1 - r^2/R^2) r / R^2 = sum_i w_i 8 / (3 sqrt(3) R_i).
    double lipschitz_bound() const;
};

// ---- line evaluators ---------------------------------------------------------------------

/// Value and slope along a line through any surface's value()/gradient() templates.
template <class S>
struct GenericLineEval {
    const S* s;
    Line3d line;

    GenericLineEval(const S& surface, const Line3d& l) : s(&surface), line(l) {}
    Interval value(const Interval& t) const {
        const auto p = line_box(line, t);
        return s->value(p[0], p[1], p[2]);
    }
    /// Encloses d/dt f(o + t d) = grad f . d over t.
    Interval slope(const Interval& t) const {
        const auto p = line_box(line, t);
        const auto g = s->gradient(p[0], p[1], p[2]);
        return g[0] * line.d[0] + g[1] * line.d[1] + g[2] * line.d[2];
    }
    double value(double t) const {
        const Vec3d p = line.at(t);
        return s->value(p[0], p[1], p[2]);
    }
};

/// Blobs along a line: only blobs whose support the line crosses, each with its exact squared
/// distance form (LineDistance2), so one blob's term is tight and the sum overestimates only
/// through the dependency between blobs.
class BlobsLineEval {
public:
    BlobsLineEval(const BlobSum& sum, const Line3d& line);
    Interval value(const Interval& t) const;
    Interval slope(const Interval& t) const;
    double value(double t) const;
    size_t active() const { return count_; }

private:
    struct Term {
        LineDistance2 dist;
        double inv_r2 = 0.0, weight = 0.0;
    };
    /// Terms live in the object itself up to kInline (no allocation per ray test), in
    /// overflow_ beyond.
    static constexpr size_t kInline = 8;
    const Term* terms() const { return overflow_.empty() ? inline_.data() : overflow_.data(); }

    std::array<Term, kInline> inline_{};
    std::vector<Term> overflow_;
    size_t count_ = 0;
    double threshold_;
};

// ---- the shape kernels -------------------------------------------------------------------

enum class ImplicitMethod { interval, sphere_tracing };

/// "interval" or "sphere-tracing"; throws Error naming the value otherwise.
ImplicitMethod parse_implicit_method(const std::string& name);
const char* to_string(ImplicitMethod m);

/// The bound on the work per ray of an implicit surface, in evaluations of one term of f (a
/// blob, or the whole polynomial of the tangle cube and Barth's sextic): sphere tracing needs
/// max_steps x terms <= this, and the interval method's span budget shrinks with the terms so
/// that its worst case stays near it. About a second per ray at worst.
inline constexpr int64_t kMaxImplicitWorkPerRay = int64_t(1) << 26;
/// Blobs in one sum: with the interval method's smallest span budget (2^14 spans), the worst
/// ray costs about kMaxImplicitWorkPerRay term evaluations.
inline constexpr size_t kMaxBlobs = size_t(1) << 12;

struct ImplicitOptions {
    Vec3 center{0.0f};  ///< world position of the object-space origin
    float scale = 1.0f;  ///< world units per object unit (uniform)
    ImplicitMethod method = ImplicitMethod::interval;
    /// Object-space length tolerance; 0 picks 1e-6 times the object box's diagonal. Interval:
    /// the t-interval width below which an unresolved interval counts as a tangential root.
    /// Sphere tracing: the smallest step (and so the widest pair of roots it can step over).
    double epsilon = 0.0;
    /// Sphere tracing only: steps before the ray is given up as a miss. max_steps times the
    /// surface's terms (blobs) may not exceed kMaxImplicitWorkPerRay.
    int max_steps = 1 << 16;
};

/// Surface S placed in the world (center + uniform scale), intersected by the chosen method.
/// Models ShapeKernel. Instantiated for TangleCube, BarthSextic and BlobSum (implicit.cpp).
template <class S>
class ImplicitKernel {
public:
    /// Throws Error if a parameter is out of range (non-positive or non-finite scale, epsilon,
    /// max_steps, radius, weight, threshold or clip; no blobs or more than kMaxBlobs; sphere
    /// tracing's max_steps x blobs above kMaxImplicitWorkPerRay).
    explicit ImplicitKernel(S surface, const ImplicitOptions& options = {});

    Aabb bounds() const { return bounds_; }
    /// First root of f along the ray with t in [ray.tmin, tmax] inside the object box; u = v = 0.
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const;
    /// Normalized gradient at p, or the direction from the object box's center where the
    /// gradient vanishes (Barth's double points) or is not finite; (0, 0, 1) as the last resort.
    Vec3 normal(Vec3 p, float u, float v) const;

    const S& surface() const { return surface_; }
    const ImplicitOptions& options() const { return options_; }
    /// The tolerance in use (object units).
    double epsilon() const { return epsilon_; }
    /// Upper bound of |grad f| over the object box, used by sphere tracing (object units).
    double lipschitz() const { return lipschitz_; }
    /// The ray in object coordinates and its parameter range inside the object box and
    /// [ray.tmin, tmax]; false if that range is empty. (Tests reuse it for their references.)
    bool object_segment(const Ray& ray, float tmax, Line3d& line, double& t0, double& t1) const;
    /// FNV-1a of the surface's parameters and the options (the scene fingerprint).
    uint64_t hash(uint64_t seed) const;

private:
    S surface_;
    ImplicitOptions options_;
    Box3d box_;
    Aabb bounds_;
    double epsilon_ = 0.0, lipschitz_ = 0.0;
};

/// JSON type "implicit": one of the built-in algebraic surfaces.
class Implicit {
public:
    static constexpr const char* kName = "implicit";
    using Kernel = std::variant<ImplicitKernel<TangleCube>, ImplicitKernel<BarthSextic>>;

    /// `surface` is "tangle-cube" or "barth-sextic" (Error listing both otherwise); `clip` is
    /// Barth's clipping half-size.
    Implicit(const std::string& surface, const ImplicitOptions& options = {}, double clip = 1.0);
    explicit Implicit(Kernel kernel) : kernel_(std::move(kernel)) {}

    Aabb bounds() const { return std::visit([](const auto& k) { return k.bounds(); }, kernel_); }
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const {
        return std::visit([&](const auto& k) { return k.intersect(ray, tmax, hit); }, kernel_);
    }
    Vec3 normal(Vec3 p, float u, float v) const {
        return std::visit([&](const auto& k) { return k.normal(p, u, v); }, kernel_);
    }
    uint64_t hash(uint64_t seed) const;
    const Kernel& kernel() const { return kernel_; }

private:
    Kernel kernel_;
};
static_assert(ShapeKernel<Implicit>);

/// JSON type "blobs": a sum of polynomial metaballs.
class Blobs {
public:
    static constexpr const char* kName = "blobs";

    explicit Blobs(BlobSum sum, const ImplicitOptions& options = {}) : kernel_(std::move(sum), options) {}

    Aabb bounds() const { return kernel_.bounds(); }
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const { return kernel_.intersect(ray, tmax, hit); }
    Vec3 normal(Vec3 p, float u, float v) const { return kernel_.normal(p, u, v); }
    uint64_t hash(uint64_t seed) const { return kernel_.hash(seed); }
    const ImplicitKernel<BlobSum>& kernel() const { return kernel_; }

private:
    ImplicitKernel<BlobSum> kernel_;
};
static_assert(ShapeKernel<Blobs>);

/// Upper bound of |grad f| over a box: the maximum over n^3 sub-boxes of the interval
/// extension of |grad f| (rigorous; tighter as n grows).
template <class S>
double lipschitz_over_box(const S& s, const Box3d& box, int n) {
    double best = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                const int idx[3] = {i, j, k};
                Interval c[3];
                for (int a = 0; a < 3; ++a) {
                    const double w = (box.hi[a] - box.lo[a]) / n;
                    c[a] = {box.lo[a] + idx[a] * w, idx[a] + 1 == n ? box.hi[a] : box.lo[a] + (idx[a] + 1) * w};
                }
                const auto g = s.gradient(c[0], c[1], c[2]);
                Interval norm2(0.0);
                for (const Interval& ga : g) norm2 += sqr(ga);
                best = std::max(best, sqrt_nonneg(norm2).hi);
            }
    return best;
}

}  // namespace thicket
