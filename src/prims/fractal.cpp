// Sphere tracing of distance-estimated fractals (fractal.h): the shared march, bounding sphere
// and normals, and the two estimators.
#include "thicket/prims/fractal.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "thicket/core/error.h"
#include "thicket/core/hash.h"

namespace thicket {
namespace {

using Point3d = std::array<double, 3>;  // as the distance estimators take it

bool finite(double x) { return std::isfinite(x); }

void check_march(const FractalMarch& m, const std::string& type) {
    if (!finite(m.center.x) || !finite(m.center.y) || !finite(m.center.z))
        throw Error(type + ": center must be finite");
    if (!(m.scale > 0.0f) || !finite(m.scale))
        throw Error(type + ": scale must be positive and finite, got " + format_number(m.scale));
    if (m.iterations < 1 || m.iterations > 1000)
        throw Error(type + ": iterations must be in 1..1000, got " + std::to_string(m.iterations));
    if (!(m.epsilon > 0.0) || !finite(m.epsilon))
        throw Error(type + ": epsilon must be positive and finite, got " + format_number(m.epsilon));
    if (!(m.step_factor > 0.0 && m.step_factor <= 1.0))
        throw Error(type + ": step-factor must be in (0, 1], got " + format_number(m.step_factor));
    if (m.max_steps < 1) throw Error(type + ": max-steps must be at least 1, got " + std::to_string(m.max_steps));
    // A ray costs up to max_steps distance estimates of `iterations` map iterations each (the
    // final bisection is bounded by double precision): each limit alone allowed 1000 x 2^24
    // iterations, minutes per ray. Their product is what bounds the work.
    const int64_t work = int64_t(m.iterations) * int64_t(m.max_steps);
    if (work > kMaxFractalWorkPerRay)
        throw Error(type + ": iterations x max-steps = " + std::to_string(m.iterations) + " x " +
                    std::to_string(m.max_steps) + " = " + std::to_string(work) + " exceeds " +
                    std::to_string(kMaxFractalWorkPerRay) + ", the bound on the work per ray (the defaults use " +
                    std::to_string(12 * (1 << 14)) + ")");
}

/// The world box of the bounding sphere, each bound rounded outward to float.
Aabb sphere_bounds(const FractalMarch& m, double radius, const std::string& type) {
    Aabb b;
    const double r = double(m.scale) * radius;
    for (int k = 0; k < 3; ++k) {
        const double lo = double(m.center[k]) - r, hi = double(m.center[k]) + r;
        const float l = float(lo), h = float(hi);
        b.min[k] = double(l) > lo ? std::nextafter(l, -INFINITY) : l;
        b.max[k] = double(h) < hi ? std::nextafter(h, INFINITY) : h;
    }
    for (int k = 0; k < 3; ++k)
        if (!finite(b.min[k]) || !finite(b.max[k]))
            throw Error(type + ": the bounds overflow float (scale " + format_number(m.scale) + ")");
    return b;
}

/// The ray in object space and its range inside the sphere of `radius` and [ray.tmin, tmax].
bool sphere_segment(const FractalMarch& m, double radius, const Ray& ray, float tmax, FractalSegment& seg) {
    const double inv = 1.0 / double(m.scale);
    double a = 0.0, b = 0.0, c = -radius * radius;
    for (int k = 0; k < 3; ++k) {
        seg.o[k] = (double(ray.org[k]) - double(m.center[k])) * inv;
        seg.d[k] = double(ray.dir[k]) * inv;
        a += seg.d[k] * seg.d[k];
        b += seg.o[k] * seg.d[k];
        c += seg.o[k] * seg.o[k];
    }
    if (!(a > 0.0) || !finite(a)) return false;
    const double disc = b * b - a * c;
    if (!(disc >= 0.0)) return false;
    // Stable roots of a t^2 + 2 b t + c: q = -(b + sign(b) sqrt(disc)), roots q / a and c / q.
    const double q = -(b + std::copysign(std::sqrt(disc), b));
    double ta = q / a, tb = q != 0.0 ? c / q : -ta;
    if (ta > tb) std::swap(ta, tb);
    seg.t0 = std::max(double(ray.tmin), ta);
    seg.t1 = std::min(double(tmax), tb);
    return seg.t0 <= seg.t1 && finite(seg.t0) && finite(seg.t1);
}

/// Sphere tracing for the first t in [t0, t1] with de(o + t d) < eps: steps of step_factor * de
/// (in object units; de is at least eps while marching, so the march always advances), then
/// bisection between the last point outside and the first inside. A thin part of the
/// eps-region that the ray crosses within one step's last eps (a grazing ray), or any part a
/// step overshoots where DE overestimates the distance, is stepped over.
/// The march gives up beyond `limit`, but its steps do not depend on it.
template <class De>
std::optional<double> march(const De& de, const FractalSegment& s, const FractalMarch& m, double limit) {
    const double dlen = std::sqrt(s.d[0] * s.d[0] + s.d[1] * s.d[1] + s.d[2] * s.d[2]);
    auto at = [&](double t) { return Point3d{s.o[0] + t * s.d[0], s.o[1] + t * s.d[1], s.o[2] + t * s.d[2]}; };
    double t = s.t0;
    double dist = de(at(t));
    if (dist < m.epsilon) return t;
    for (int i = 0; i < m.max_steps && t <= limit; ++i) {
        double tn = t + m.step_factor * dist / dlen;
        const bool last = !(tn < s.t1);
        if (last) tn = s.t1;
        const double dn = de(at(tn));
        if (dn < m.epsilon) {
            // de(t) >= eps > de(tn): bisect to double resolution (the crossing may be a jump of
            // DE where the escape iteration count changes; any crossing point is then the hit).
            double lo = t, hi = tn;
            for (int k = 0; k < 100; ++k) {
                const double mid = 0.5 * (lo + hi);
                if (!(mid > lo && mid < hi) || hi - lo <= 1e-7 * m.epsilon / dlen) break;
                (de(at(mid)) < m.epsilon ? hi : lo) = mid;
            }
            return hi;
        }
        if (last) return std::nullopt;
        t = tn;
        dist = dn;
    }
    return std::nullopt;
}

/// The first hit of the eps-region in [ray.tmin, tmax] (u = v = 0). The march runs over the whole
/// segment inside the bounding sphere, not cut at tmax: a structure calls this with its current
/// closest hit as tmax, and must get the same hit as brute force.
template <class De>
bool march_hit(const De& de, const FractalMarch& m, double radius, const Ray& ray, float tmax, ShapeHit& hit) {
    // Hits up to the next float count: they round to tmax itself.
    const double limit = double(std::nextafter(tmax, kInfinity));
    FractalSegment seg;
    if (!(ray.tmin <= tmax) || !sphere_segment(m, radius, ray, kInfinity, seg) || seg.t0 > limit) return false;
    const auto t = march(de, seg, m, limit);
    if (!t || !(float(*t) <= tmax)) return false;
    hit = {float(*t), 0.0f, 0.0f};
    return true;
}

/// Central differences of de at q with step h, normalized; radial or +z where they vanish.
template <class De>
Vec3 de_normal(const De& de, const Point3d& q, double h) {
    Point3d g;
    for (int k = 0; k < 3; ++k) {
        Point3d a = q, b = q;
        a[k] += h;
        b[k] -= h;
        g[k] = de(a) - de(b);
    }
    for (const Point3d& v : {g, q}) {
        const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (len > 0.0 && finite(len)) return Vec3(float(v[0] / len), float(v[1] / len), float(v[2] / len));
    }
    return Vec3(0.0f, 0.0f, 1.0f);
}

Point3d object_point(const FractalMarch& m, Vec3 p) {
    return {(double(p.x) - m.center.x) / m.scale, (double(p.y) - m.center.y) / m.scale,
            (double(p.z) - m.center.z) / m.scale};
}

/// Margin of the bounding sphere over the set's radius: the eps-region extends beyond the set
/// by about 4 eps at most where DE underestimates the distance by its worst factor (Koebe's 1/4
/// for the complex case), so 16 eps plus 1% leaves room; tests check DE > eps on the sphere.
double bounding_margin(double set_radius, double eps) { return 0.01 * set_radius + 16.0 * eps; }

uint64_t hash_march(const FractalMarch& m, uint64_t h) {
    h = fnv1a(&m.center, sizeof m.center, h);
    h = fnv1a(&m.scale, sizeof m.scale, h);
    h = fnv1a(&m.iterations, sizeof m.iterations, h);
    h = fnv1a(&m.epsilon, sizeof m.epsilon, h);
    h = fnv1a(&m.step_factor, sizeof m.step_factor, h);
    return fnv1a(&m.max_steps, sizeof m.max_steps, h);
}

uint64_t hash_params(const JuliaParams& p, uint64_t h) {
    h = fnv1a(p.c.data(), sizeof p.c, h);
    h = fnv1a(&p.w, sizeof p.w, h);
    h = fnv1a(&p.bailout, sizeof p.bailout, h);
    return hash_march(p.march, h);
}

uint64_t hash_params(const MandelbulbParams& p, uint64_t h) {
    h = fnv1a(&p.power, sizeof p.power, h);
    h = fnv1a(&p.bailout, sizeof p.bailout, h);
    return hash_march(p.march, h);
}

}  // namespace

// ---- What both share ----------------------------------------------------------------------

template <class Derived, class P>
void DistanceFractal<Derived, P>::bound(double set_radius, double slice_radius, const char* type) {
    set_radius_ = set_radius;
    bound_radius_ = slice_radius + bounding_margin(set_radius, p_.march.epsilon);
    bounds_ = sphere_bounds(p_.march, bound_radius_, type);
}

template <class Derived, class P>
uint64_t DistanceFractal<Derived, P>::hash(uint64_t seed) const {
    return hash_params(p_, seed);
}

template <class Derived, class P>
bool DistanceFractal<Derived, P>::object_segment(const Ray& ray, float tmax, FractalSegment& seg) const {
    return sphere_segment(p_.march, bound_radius_, ray, tmax, seg);
}

template <class Derived, class P>
bool DistanceFractal<Derived, P>::intersect(const Ray& ray, float tmax, ShapeHit& hit) const {
    const auto de = [this](const Point3d& q) { return static_cast<const Derived*>(this)->distance(q); };
    return march_hit(de, p_.march, bound_radius_, ray, tmax, hit);
}

template <class Derived, class P>
Vec3 DistanceFractal<Derived, P>::normal(Vec3 p, float, float) const {
    const auto de = [this](const Point3d& q) { return static_cast<const Derived*>(this)->distance(q); };
    return de_normal(de, object_point(p_.march, p), 0.5 * p_.march.epsilon);
}

// ---- Julia -------------------------------------------------------------------------------

Julia::Julia(const Params& p) : DistanceFractal(p) {
    const std::string type = "julia";
    check_march(p.march, type);
    for (double x : p.c)
        if (!finite(x)) throw Error(type + ": c must be finite, got component " + format_number(x));
    if (!finite(p.w)) throw Error(type + ": w must be finite");
    const double cn = std::sqrt(p.c[0] * p.c[0] + p.c[1] * p.c[1] + p.c[2] * p.c[2] + p.c[3] * p.c[3]);
    const double radius = 0.5 + std::sqrt(0.25 + cn);
    if (!(p.bailout >= radius) || !finite(p.bailout))
        throw Error(type + ": bailout " + format_number(p.bailout) + " is below the set's radius " + format_number(radius) +
                    " (0.5 + sqrt(0.25 + |c|)): points of the set would count as escaped");
    if (!(std::fabs(p.w) < radius))
        throw Error(type + ": the slice w = " + format_number(p.w) + " misses the set (|w| must be below " +
                    format_number(radius) + ")");
    bound(radius, std::sqrt(radius * radius - p.w * p.w), "julia");
}

double Julia::distance(const std::array<double, 3>& q) const {
    // z = (a, v) with v = (b, c, d): z^2 = (a^2 - |v|^2, 2 a v); |z'| <- 2 |z| |z'| (|z z'| = |z| |z'|).
    double a = q[0], b = q[1], c = q[2], d = p_.w;
    double r2 = a * a + b * b + c * c + d * d;
    double dz = 1.0;
    const double bail2 = p_.bailout * p_.bailout;
    bool escaped = r2 > bail2;
    for (int i = 0; i < p_.march.iterations && !escaped; ++i) {
        dz *= 2.0 * std::sqrt(r2);
        const double na = a * a - b * b - c * c - d * d + p_.c[0];
        b = 2.0 * a * b + p_.c[1];
        c = 2.0 * a * c + p_.c[2];
        d = 2.0 * a * d + p_.c[3];
        a = na;
        r2 = a * a + b * b + c * c + d * d;
        escaped = r2 > bail2;
    }
    if (!escaped) return 0.0;
    const double r = std::sqrt(r2);
    return 0.5 * r * std::log(r) / dz;
}

// ---- Mandelbulb --------------------------------------------------------------------------

Mandelbulb::Mandelbulb(const Params& p) : DistanceFractal(p) {
    const std::string type = "mandelbulb";
    check_march(p.march, type);
    if (!(p.power >= 2.0 && p.power <= 32.0))
        throw Error(type + ": power must be in [2, 32], got " + format_number(p.power));
    const double radius = std::pow(2.0, 1.0 / (p.power - 1.0));
    if (!(p.bailout >= radius) || !finite(p.bailout))
        throw Error(type + ": bailout " + format_number(p.bailout) + " is below the set's radius " + format_number(radius) +
                    " (2^(1/(power-1))): points of the set would count as escaped");
    bound(radius, radius, "mandelbulb");
}

double Mandelbulb::distance(const std::array<double, 3>& q) const {
    const double n = p_.power;
    double x = q[0], y = q[1], z = q[2];
    double r = std::sqrt(x * x + y * y + z * z);
    double dr = 1.0;
    bool escaped = r > p_.bailout;
    for (int i = 0; i < p_.march.iterations && !escaped; ++i) {
        // z^n in spherical coordinates: radius r^n, both angles times n (0 stays 0).
        const double theta = r > 0.0 ? std::acos(std::clamp(z / r, -1.0, 1.0)) * n : 0.0;
        const double phi = std::atan2(y, x) * n;
        const double rn1 = std::pow(r, n - 1.0);
        dr = n * rn1 * dr + 1.0;
        const double rn = rn1 * r;
        x = rn * std::sin(theta) * std::cos(phi) + q[0];
        y = rn * std::sin(theta) * std::sin(phi) + q[1];
        z = rn * std::cos(theta) + q[2];
        r = std::sqrt(x * x + y * y + z * z);
        escaped = r > p_.bailout;
    }
    if (!escaped) return 0.0;
    return 0.5 * std::log(r) * r / dr;
}

template class DistanceFractal<Julia, JuliaParams>;
template class DistanceFractal<Mandelbulb, MandelbulbParams>;

}  // namespace thicket
