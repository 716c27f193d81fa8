#include "support/double_reference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <vector>

#include "thicket/core/triangle.h"
#include "thicket/util/parallel.h"

namespace thicket::testing {

namespace {

// What makes a hit ill-conditioned, i.e. one that float tests may legitimately answer otherwise:
// - |det| / (|d| |e1| |e2|) below kGrazing: the ray nearly in the triangle's plane, or a needle
//   triangle (the README's degenerate rule, 1e-6, is far inside this);
// - a barycentric coordinate within kEdge of 0: on an edge or vertex, where the neighbour sharing
//   it answers instead, or nothing (Moller is not watertight);
// - t within kBoundary of the interval's ends, in units of the float rounding of t: rays that
//   start on a surface.
constexpr double kGrazing = 1e-2;
constexpr double kEdge = 1e-4;
constexpr double kBoundary = 1e-4;

struct D3 {
    double x, y, z;
};
D3 d3(const Vec3& v) { return {v.x, v.y, v.z}; }
D3 sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double len(D3 a) { return std::sqrt(dot(a, a)); }

/// Moller-Trumbore in double, without any tolerance: barycentrics and t even when outside.
struct DoubleHit {
    bool valid = false;  ///< det != 0
    double t = 0, u = 0, v = 0, conditioning = 0, scale = 0;
    bool inside(const Ray& r) const {
        return valid && u >= 0 && v >= 0 && u + v <= 1 && t >= r.tmin && t <= r.tmax;
    }
};

DoubleHit double_moller(const Scene& scene, uint32_t prim, const Ray& ray) {
    const D3 v0 = d3(scene.mesh.vertex(prim, 0)), v1 = d3(scene.mesh.vertex(prim, 1)),
             v2 = d3(scene.mesh.vertex(prim, 2));
    const D3 o = d3(ray.org), d = d3(ray.dir);
    const D3 e1 = sub(v1, v0), e2 = sub(v2, v0);
    const D3 p = cross(d, e2);
    const double det = dot(e1, p);
    DoubleHit h;
    if (det == 0.0) return h;
    const D3 s = sub(o, v0);
    const D3 q = cross(s, e1);
    h.valid = true;
    h.u = dot(s, p) / det;
    h.v = dot(d, q) / det;
    h.t = dot(e2, q) / det;
    h.conditioning = std::fabs(det) / (len(d) * len(e1) * len(e2));
    h.scale = (len(s) + len(e1) + len(e2)) / len(d);  // t's rounding is relative to this
    return h;
}

bool ill_conditioned(const DoubleHit& h, const Ray& ray) {
    if (!h.valid || h.conditioning < kGrazing) return true;
    if (std::min({h.u, h.v, 1.0 - h.u - h.v}) < kEdge) return true;
    return std::fabs(h.t - double(ray.tmin)) <= kBoundary * h.scale ||
           std::fabs(h.t - double(ray.tmax)) <= kBoundary * h.scale;
}

/// The reference's closest hit: smallest t over every triangle whose double hit is inside.
std::pair<uint32_t, double> closest_double(const Scene& scene, const Ray& ray) {
    uint32_t best = kNoPrim;
    double best_t = INFINITY;
    const uint32_t n = uint32_t(scene.mesh.triangle_count());
    for (uint32_t prim = 0; prim < n; ++prim) {
        const DoubleHit h = double_moller(scene, prim, ray);
        if (h.inside(ray) && h.t < best_t) best = prim, best_t = h.t;
    }
    return {best, best_t};
}

}  // namespace

FilterCheck check_against_double_reference(const Scene& scene, const std::string& isect, std::span<const Ray> rays,
                                           std::span<const Hit> hits) {
    const bool watertight = isect == "watertight";
    FilterCheck c;
    c.rays = rays.size();
    std::mutex mutex;
    parallel_for(rays.size(), 16, 0, [&](size_t begin, size_t end) {
        FilterCheck local;
        std::string first;
        for (size_t i = begin; i < end; ++i) {
            const Ray& ray = rays[i];
            const Hit& got = hits[i];
            const auto [want, want_t] = closest_double(scene, ray);
            if ((!got.found() && want == kNoPrim) || (got.found() && got.prim == want)) {
                ++local.agree;
                continue;
            }
            if (got.found() && want != kNoPrim && std::fabs(double(got.t) - want_t) <= 1e-5 * std::fabs(want_t)) {
                ++local.agree;  // a tie: two triangles meet at that point
                continue;
            }
            // They differ. The hit that one side has and the other lacks (or finds farther) must be
            // ill-conditioned; when both hit, both must be (each one's absence is the question).
            bool explained = true;
            if (want != kNoPrim && !(got.found() && double(got.t) < want_t)) {
                const DoubleHit h = double_moller(scene, want, ray);
                explained = explained && ill_conditioned(h, ray);
                // Did the float test report it, and the filter drop it?
                const Vec3 v0 = scene.mesh.vertex(want, 0), v1 = scene.mesh.vertex(want, 1),
                           v2 = scene.mesh.vertex(want, 2);
                TriangleHit fh;
                if (watertight ? intersect_watertight(v0, v1, v2, ray, ray.tmax, fh)
                               : intersect_moller(v0, v1, v2, ray, ray.tmax, fh))
                    ++local.filter_rejections;
            }
            if (got.found() && !(want != kNoPrim && want_t < double(got.t)))
                explained = explained && ill_conditioned(double_moller(scene, got.prim, ray), ray);
            if (explained) {
                ++local.ill_conditioned;
            } else {
                ++local.unexplained;
                if (first.empty()) {
                    char buf[256];
                    std::snprintf(buf, sizeof buf, "ray %zu: got prim %u t %.9g, double-precision prim %u t %.9g", i,
                                  got.found() ? got.prim : kNoPrim, double(got.t), want, want_t);
                    first = buf;
                }
            }
        }
        std::lock_guard<std::mutex> lock(mutex);
        c.agree += local.agree;
        c.ill_conditioned += local.ill_conditioned;
        c.filter_rejections += local.filter_rejections;
        c.unexplained += local.unexplained;
        if (c.first_unexplained.empty()) c.first_unexplained = first;
    });
    return c;
}

FilterCheck check_named_primitives(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits) {
    FilterCheck c;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit& got = hits[i];
        if (!got.found()) continue;
        ++c.rays;
        const Ray& ray = rays[i];
        const bool named_exists = got.prim < scene.mesh.triangle_count();
        const DoubleHit h = named_exists ? double_moller(scene, got.prim, ray) : DoubleHit{};
        if (h.inside(ray) && std::fabs(h.t - double(got.t)) <= 1e-5 * std::max(h.scale, std::fabs(h.t))) {
            ++c.agree;
        } else if (named_exists && ill_conditioned(h, ray)) {
            ++c.ill_conditioned;
        } else {
            ++c.unexplained;
            if (c.first_unexplained.empty()) {
                char buf[256];
                std::snprintf(buf, sizeof buf, "ray %zu: prim %u at t %.9g, in double precision t %.9g u %.3g v %.3g", i,
                              got.prim, double(got.t), h.t, h.u, h.v);
                c.first_unexplained = buf;
            }
        }
    }
    return c;
}

}  // namespace thicket::testing
