#include "thicket/bench/arbiter.h"

#include <algorithm>
#include <cmath>

#include "thicket/core/vec3.h"
#include "thicket/scene/instance.h"

namespace thicket {

namespace {

/// Distance from p to triangle abc (closest point by Voronoi regions, Ericson 2005, 5.1.5).
double point_triangle_distance(const Vec3d& p, const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    const Vec3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return length(ap);
    const Vec3d bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return length(bp);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return length(p - (a + ab * (d1 / (d1 - d3))));
    const Vec3d cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return length(cp);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return length(p - (a + ac * (d2 / (d2 - d6))));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const double denom = 1.0 / (va + vb + vc);
    return length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

/// Distance from the 2D origin to the segment pq.
double origin_segment_distance(double px, double py, double qx, double qy) {
    const double ex = qx - px, ey = qy - py, len2 = ex * ex + ey * ey;
    const double s = len2 > 0 ? std::clamp(-(px * ex + py * ey) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(px + s * ex, py + s * ey);
}

/// How far the ray through o along d may move sideways and still cross triangle v (> 0), or how
/// far it misses it (< 0): the triangle projected onto the plane across the ray, where the ray is
/// the origin.
double sideways_depth(const Vec3d& o, const Vec3d& d, const Vec3d (&v)[3]) {
    const Vec3d n = normalize(d);
    // Of the axes, the one least along the ray gives a well-conditioned first basis vector.
    const Vec3d axis = std::fabs(n.x) <= std::fabs(n.y) && std::fabs(n.x) <= std::fabs(n.z) ? Vec3d{1, 0, 0}
                       : std::fabs(n.y) <= std::fabs(n.z)                                  ? Vec3d{0, 1, 0}
                                                                                           : Vec3d{0, 0, 1};
    const Vec3d e1 = normalize(cross(n, axis));
    const Vec3d e2 = cross(n, e1);
    double x[3], y[3];
    for (int i = 0; i < 3; ++i) {
        const Vec3d r = v[i] - o;
        x[i] = dot(r, e1);
        y[i] = dot(r, e2);
    }
    double nearest = INFINITY;
    int positive = 0, negative = 0;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        nearest = std::min(nearest, origin_segment_distance(x[i], y[i], x[j], y[j]));
        // Which side of edge ij the origin lies on.
        const double side = (x[j] - x[i]) * (0.0 - y[i]) - (y[j] - y[i]) * (0.0 - x[i]);
        positive += side > 0;
        negative += side < 0;
    }
    const bool inside = positive == 3 || negative == 3;
    return inside ? nearest : -nearest;
}

}  // namespace

RoundingArbiter::RoundingArbiter(const Scene& scene) : scene_(scene) {}

std::optional<RoundingArbiter::Triangle> RoundingArbiter::triangle(uint32_t prim) const {
    const Instance* instance = nullptr;
    uint32_t scene_prim = prim;
    if (!scene_.instances.empty()) {
        if (scene_.instance_first.size() != scene_.instances.size() + 1 || prim >= scene_.instanced_primitive_count())
            return std::nullopt;
        const auto it = std::upper_bound(scene_.instance_first.begin(), scene_.instance_first.end(), uint64_t(prim));
        const size_t i = size_t(it - scene_.instance_first.begin()) - 1;
        instance = &scene_.instances[i];
        scene_prim = scene_.geometry(instance->geometry).first + uint32_t(prim - scene_.instance_first[i]);
    }
    if (scene_prim >= scene_.primitive_count()) return std::nullopt;
    const PrimRef ref = scene_.locate(scene_prim);
    if (ref.shape) return std::nullopt;
    Triangle tri;
    for (int c = 0; c < 3; ++c) {
        const Vec3d p(scene_.mesh.vertex(ref.index, c));
        if (!instance) {
            tri.v[c] = p;
            continue;
        }
        for (int a = 0; a < 3; ++a) {
            const auto& m = instance->transform.m[a];
            tri.v[c][a] = double(m[0]) * p.x + double(m[1]) * p.y + double(m[2]) * p.z + double(m[3]);
        }
    }
    if (instance) tri.scale = std::max(1.0, transform_condition(instance->transform) / 3.0);
    return tri;
}

double RoundingArbiter::delta(const Ray& ray, double t, double scale) {
    const Vec3d o(ray.org), d(ray.dir);
    const double reach = std::max({std::fabs(o.x), std::fabs(o.y), std::fabs(o.z)}) +
                         std::fabs(t) * std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
    return kArbiterUlps * 0x1p-24 * reach * scale;
}

RoundingArbiter::Verdict RoundingArbiter::judge(const Ray& ray, uint32_t prim, double t_asked) const {
    Verdict out;
    const std::optional<Triangle> tri = triangle(prim);
    if (!tri) return out;
    out.triangle = true;
    const Vec3d o(ray.org), d(ray.dir);
    const Vec3d normal = cross(tri->v[1] - tri->v[0], tri->v[2] - tri->v[0]);
    const double facing = dot(normal, d);
    out.t = facing != 0.0 ? dot(normal, tri->v[0] - o) / facing : NAN;
    out.depth = sideways_depth(o, d, tri->v);
    out.point_distance = point_triangle_distance(o + d * t_asked, tri->v[0], tri->v[1], tri->v[2]);
    out.delta = delta(ray, t_asked, tri->scale);
    out.scale = tri->scale;
    return out;
}

bool RoundingArbiter::possible(const Ray& ray, const Hit& hit) const {
    const Verdict v = judge(ray, hit.prim, hit.t);
    return v.triangle && v.point_distance <= v.delta;
}

bool RoundingArbiter::certain(const Ray& ray, uint32_t prim) const {
    const Verdict v = judge(ray, prim, 0.0);  // t and depth do not depend on the point asked
    if (!v.triangle || !std::isfinite(v.t)) return false;
    const double slack = delta(ray, v.t, v.scale);
    const double along = length(Vec3d(ray.dir));
    return v.depth > slack && (v.t - double(ray.tmin)) * along > slack && (double(ray.tmax) - v.t) * along > slack;
}

bool RoundingArbiter::candidate_within_rounding(const Ray& ray, const Hit& reference, const Hit& candidate) const {
    if ((reference.found() && !triangle(reference.prim)) || (candidate.found() && !triangle(candidate.prim)))
        return false;
    if (candidate.found() && !possible(ray, candidate)) return false;
    const bool reference_nearer = reference.found() && (!candidate.found() || reference.t < candidate.t);
    if (reference_nearer && reference.prim != candidate.prim && certain(ray, reference.prim)) return false;
    return true;
}

}  // namespace thicket
