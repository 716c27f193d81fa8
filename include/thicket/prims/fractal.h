#pragma once
/// Distance-estimated fractals as shape kernels (shape.h), ray traced by sphere tracing:
///   Julia       quaternion Julia set z <- z^2 + c, 3-D slice (x, y, z, w) at a fixed w (Hart,
///               Sandin & Kauffman, SIGGRAPH '89), DE = 0.5 |z| log|z| / |z'|, |z'| <- 2 |z| |z'|
///   Mandelbulb  z <- z^n + p in spherical coordinates (White & Nylander 2009), DE =
///               0.5 log(r) r / dr, dr <- n r^(n-1) dr + 1
/// The surface is the epsilon-isosurface of the estimator: a ray hits where DE first drops below
/// epsilon, inside a bounding sphere that provably contains the set (plus a margin). Points that
/// do not escape within `iterations` have DE = 0. docs/implicit-fractal.md states the failure modes.
#include <array>
#include <cstdint>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"
#include "thicket/prims/shape.h"

namespace thicket {

/// Placement and marching parameters shared by both fractals. Lengths are in object units (the
/// fractal at its own size, about 1), so a placed fractal is the same shape at any scale.
/// Largest iterations x max_steps a fractal takes: bounds the map iterations one ray may cost
/// (about 20 times the defaults' 196,608; tens of milliseconds per ray).
inline constexpr int64_t kMaxFractalWorkPerRay = int64_t(1) << 22;

struct FractalMarch {
    Vec3 center{0.0f};  ///< world position of the object-space origin
    float scale = 1.0f;  ///< world units per object unit (uniform)
    int iterations = 12;       ///< iterations of the escape-time map per DE evaluation
    double epsilon = 1e-3;     ///< the surface is DE = epsilon
    double step_factor = 1.0;  ///< sphere-tracing step = step_factor * DE (< 1: more careful)
    int max_steps = 1 << 14;   ///< steps before a ray is given up as a miss
};

/// A sphere in object space: what a fractal's ray segment is clipped to.
struct FractalSegment {
    std::array<double, 3> o{}, d{};  ///< the ray in object space
    double t0 = 0.0, t1 = 0.0;       ///< its parameter range inside the bounding sphere and [tmin, tmax]
};

/// What both fractals share: the parameters that place and march them (Params::march), a
/// bounding sphere that provably holds the set, and sphere tracing of Derived::distance inside it.
/// Derived's constructor checks its parameters and calls bound() (defined in fractal.cpp, made
/// for Julia and Mandelbulb there).
template <class Derived, class P>
class DistanceFractal {
public:
    using Params = P;

    Aabb bounds() const { return bounds_; }
    /// First t in [ray.tmin, tmax] inside the bounding sphere where DE < epsilon (t = the start
    /// of the segment if DE < epsilon there: a ray starting inside is blocked at once); u = v = 0.
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const;
    /// Central differences of DE (step epsilon / 2), normalized; the radial direction where they
    /// vanish (inside the set), (0, 0, 1) at the center.
    Vec3 normal(Vec3 p, float u, float v) const;
    /// The radius beyond which every point escapes (Derived says why for its map).
    double set_radius() const { return set_radius_; }
    /// The bounding sphere's radius in object space (the slice's radius plus a margin).
    double bounding_radius() const { return bound_radius_; }
    /// The ray in object space and its range inside the bounding sphere and [ray.tmin, tmax].
    bool object_segment(const Ray& ray, float tmax, FractalSegment& seg) const;
    const Params& params() const { return p_; }
    /// The parameters' hash (every field, march included), chained on `seed`.
    uint64_t hash(uint64_t seed) const;

protected:
    explicit DistanceFractal(const Params& p) : p_(p) {}
    /// Sets the set's radius, the sphere's (the slice's radius `slice_radius` plus the margin
    /// epsilon needs) and the world box; throws Error naming `type` if the box overflows float.
    void bound(double set_radius, double slice_radius, const char* type);

    Params p_;

private:
    double set_radius_ = 0.0, bound_radius_ = 0.0;
    Aabb bounds_;
};

struct JuliaParams {
    std::array<double, 4> c{-0.2, 0.6, 0.2, 0.2};  ///< the Julia constant (1, i, j, k parts)
    double w = 0.0;                               ///< the slice: the 4th coordinate of every point
    double bailout = 4.0;                         ///< escape radius (>= the set's radius)
    FractalMarch march{};
};

/// Quaternion Julia set; JSON type "julia". Its set radius is 0.5 + sqrt(0.25 + |c|): no point
/// of the 4-D set lies farther from the origin (beyond it |z^2 + c| >= |z|^2 - |c| > |z|, and the
/// excess grows).
class Julia : public DistanceFractal<Julia, JuliaParams> {
public:
    static constexpr const char* kName = "julia";

    /// Throws Error if a parameter is out of range (non-finite values, iterations outside
    /// 1..1000, epsilon or scale not positive, step_factor outside (0, 1], bailout below the
    /// set's radius, a slice |w| beyond the set).
    explicit Julia(const Params& p);
    /// The distance estimate at an object-space point (0 if it does not escape).
    double distance(const std::array<double, 3>& q) const;
};
static_assert(ShapeKernel<Julia>);

struct MandelbulbParams {
    double power = 8.0;    ///< n, real, 2..32
    double bailout = 2.0;  ///< escape radius (>= the set's radius)
    FractalMarch march{.iterations = 10};
};

/// The Mandelbulb; JSON type "mandelbulb". Its set radius is 2^(1/(n-1)): beyond it
/// |z^n + p| >= |z|^n - |p| > |z| from the first step on (|z_1| = |p|), so every point farther out
/// escapes. 1.104 for n = 8.
class Mandelbulb : public DistanceFractal<Mandelbulb, MandelbulbParams> {
public:
    static constexpr const char* kName = "mandelbulb";

    /// Throws Error as Julia does, and for a power outside [2, 32].
    explicit Mandelbulb(const Params& p);
    /// The distance estimate at an object-space point (0 if it does not escape).
    double distance(const std::array<double, 3>& q) const;
};
static_assert(ShapeKernel<Mandelbulb>);

}  // namespace thicket
