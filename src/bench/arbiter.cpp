#include "thicket/bench/arbiter.h"

#include <algorithm>
#include <cmath>

#include "thicket/core/vec3.h"
#include "thicket/geometry/weld.h"
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

/// The plane across the ray through o along d, where the ray is the origin: a point's
/// coordinates there say how far sideways it lies from the ray.
struct AcrossRay {
    Vec3d o, e1, e2;
    AcrossRay(const Vec3d& origin, const Vec3d& d) : o(origin) {
        const Vec3d n = normalize(d);
        // Of the axes, the one least along the ray gives a well-conditioned first basis vector.
        const Vec3d axis = std::fabs(n.x) <= std::fabs(n.y) && std::fabs(n.x) <= std::fabs(n.z) ? Vec3d{1, 0, 0}
                           : std::fabs(n.y) <= std::fabs(n.z)                                  ? Vec3d{0, 1, 0}
                                                                                               : Vec3d{0, 0, 1};
        e1 = normalize(cross(n, axis));
        e2 = cross(n, e1);
    }
    void project(const Vec3d& p, double& x, double& y) const {
        const Vec3d r = p - o;
        x = dot(r, e1);
        y = dot(r, e2);
    }
};

/// Which side of the projected line through (ax, ay), (bx, by) the point (px, py) lies on.
double side_of(double ax, double ay, double bx, double by, double px, double py) {
    return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

/// How far a ray may move sideways and still cross a triangle (> 0), or how far it misses it
/// (< 0), from the triangle's corners (x[i], y[i]) projected across the ray (AcrossRay), where
/// the ray is the origin.
double projected_depth(const double (&x)[3], const double (&y)[3]) {
    double nearest = INFINITY;
    int positive = 0, negative = 0;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        nearest = std::min(nearest, origin_segment_distance(x[i], y[i], x[j], y[j]));
        // Which side of edge ij the origin lies on.
        const double side = side_of(x[i], y[i], x[j], y[j], 0.0, 0.0);
        positive += side > 0;
        negative += side < 0;
    }
    const bool inside = positive == 3 || negative == 3;
    return inside ? nearest : -nearest;
}

/// projected_depth of triangle v for the ray through o along d.
double sideways_depth(const Vec3d& o, const Vec3d& d, const Vec3d (&v)[3]) {
    const AcrossRay across(o, d);
    double x[3], y[3];
    for (int i = 0; i < 3; ++i) across.project(v[i], x[i], y[i]);
    return projected_depth(x, y);
}

/// Where the ray through o along d meets the plane of triangle v (NaN: parallel to it).
double plane_t(const Vec3d& o, const Vec3d& d, const Vec3d (&v)[3]) {
    const Vec3d normal = cross(v[1] - v[0], v[2] - v[0]);
    const double facing = dot(normal, d);
    return facing != 0.0 ? dot(normal, v[0] - o) / facing : NAN;
}

}  // namespace

RoundingArbiter::RoundingArbiter(const Scene& scene) : scene_(scene) {
    // Vertices welded by their exact position (meshes that repeat a vertex per face still share
    // edges), then each welded vertex's triangles, in compressed rows.
    const TriangleMesh& mesh = scene.mesh;
    welded_ = weld_by_position(mesh.positions);
    const size_t triangles = mesh.indices.size() / 3;
    ring_first_.assign(mesh.positions.size() + 1, 0);
    for (uint32_t index : mesh.indices) ++ring_first_[welded_[index] + 1];
    for (size_t v = 0; v < mesh.positions.size(); ++v) ring_first_[v + 1] += ring_first_[v];
    ring_.resize(mesh.indices.size());
    std::vector<uint32_t> fill(ring_first_.begin(), ring_first_.end() - 1);
    for (size_t t = 0; t < triangles; ++t)
        for (int c = 0; c < 3; ++c) ring_[fill[welded_[mesh.indices[3 * t + size_t(c)]]]++] = uint32_t(t);
}

std::optional<RoundingArbiter::Located> RoundingArbiter::locate(uint32_t prim) const {
    Located out;
    uint32_t scene_prim = prim;
    if (!scene_.instances.empty()) {
        if (scene_.instance_first.size() != scene_.instances.size() + 1 || prim >= scene_.instanced_primitive_count())
            return std::nullopt;
        const auto it = std::upper_bound(scene_.instance_first.begin(), scene_.instance_first.end(), uint64_t(prim));
        const size_t i = size_t(it - scene_.instance_first.begin()) - 1;
        out.instance = &scene_.instances[i];
        scene_prim = scene_.geometry(out.instance->geometry).first + uint32_t(prim - scene_.instance_first[i]);
        out.scale = std::min(kArbiterMaxScale, std::max(1.0, transform_condition(out.instance->transform) / 3.0));
    }
    if (scene_prim >= scene_.primitive_count()) return std::nullopt;
    const PrimRef ref = scene_.locate(scene_prim);
    if (ref.shape) return std::nullopt;
    out.triangle = ref.index;
    return out;
}

RoundingArbiter::Triangle RoundingArbiter::world(const Located& at, uint32_t mesh_triangle) const {
    Triangle tri;
    tri.scale = at.scale;
    for (int c = 0; c < 3; ++c) {
        const Vec3d p(scene_.mesh.vertex(mesh_triangle, c));
        if (!at.instance) {
            tri.v[c] = p;
            continue;
        }
        for (int a = 0; a < 3; ++a) {
            const auto& m = at.instance->transform.m[a];
            tri.v[c][a] = double(m[0]) * p.x + double(m[1]) * p.y + double(m[2]) * p.z + double(m[3]);
        }
    }
    return tri;
}

std::optional<RoundingArbiter::Triangle> RoundingArbiter::triangle(uint32_t prim) const {
    const std::optional<Located> at = locate(prim);
    if (!at) return std::nullopt;
    return world(*at, at->triangle);
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
    out.t = plane_t(o, d, tri->v);
    out.depth = sideways_depth(o, d, tri->v);
    out.point_distance = point_triangle_distance(o + d * t_asked, tri->v[0], tri->v[1], tri->v[2]);
    out.delta = delta(ray, t_asked, tri->scale);
    out.scale = tri->scale;
    return out;
}

bool RoundingArbiter::possible(const Ray& ray, const Hit& hit) const {
    const Verdict v = judge(ray, hit.prim, hit.t);
    if (!v.triangle || !(v.point_distance <= v.delta)) return false;
    // Within the ray's interval, widened by rounding only: a hit behind the origin or past tmax
    // is no hit, however close to its triangle.
    const double along = length(Vec3d(ray.dir));
    const double slack = along > 0.0 ? v.delta / along : 0.0;
    return double(hit.t) >= double(ray.tmin) - slack && double(hit.t) <= double(ray.tmax) + slack;
}

RoundingArbiter::Certainty RoundingArbiter::certainty(const Ray& ray, uint32_t prim) const {
    Certainty out;
    const std::optional<Located> at = locate(prim);
    if (!at) return out;
    const Vec3d o(ray.org), d(ray.dir);
    const double along = length(d);
    if (!(along > 0.0)) return out;
    const TriangleMesh& mesh = scene_.mesh;
    // The triangles around the primitive's welded vertices (itself included), each once.
    std::vector<uint32_t> around;
    for (int c = 0; c < 3; ++c) {
        const uint32_t v = welded_[mesh.indices[3 * size_t(at->triangle) + size_t(c)]];
        around.insert(around.end(), ring_.begin() + ring_first_[v], ring_.begin() + ring_first_[v + 1]);
    }
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());

    const double own_t = plane_t(o, d, world(*at, at->triangle).v);
    if (!std::isfinite(own_t)) return out;
    const double slack = delta(ray, own_t, at->scale);

    // Projected across the ray: the union of these triangles covers every ray within `slack` of
    // this one when the origin lies inside one of them and `slack` from every edge of the union's
    // boundary. An edge is inside the union when exactly two of the triangles share it and lie on
    // its two sides (a fold or a non-manifold edge is boundary). Only triangles the ray meets at
    // least `slack` inside its interval count: one behind the origin or past tmax covers nothing.
    const AcrossRay across(o, d);
    struct Projected {
        uint32_t vertex[3];
        double x[3], y[3];
    };
    std::vector<Projected> flat;
    bool inside = false;
    double t_covering = INFINITY, t_reach = -INFINITY;  // nearest t of a triangle alone covering, farthest reachable
    for (uint32_t tri : around) {
        const Triangle w = world(*at, tri);
        const double t = plane_t(o, d, w.v);
        Projected p;
        for (int c = 0; c < 3; ++c) {
            p.vertex[c] = welded_[mesh.indices[3 * size_t(tri) + size_t(c)]];
            across.project(w.v[c], p.x[c], p.y[c]);
        }
        const double depth = projected_depth(p.x, p.y);
        if (!std::isfinite(t)) {
            if (depth > -slack) return out;  // edge-on to the ray within reach: no certain crossing
            continue;
        }
        if (!((t - double(ray.tmin)) * along > slack && (double(ray.tmax) - t) * along > slack)) continue;
        inside = inside || depth > 0.0;
        if (depth > slack) t_covering = std::min(t_covering, t);
        if (depth > -slack) t_reach = std::max(t_reach, t);
        flat.push_back(p);
    }
    if (!inside) return out;
    double nearest = INFINITY;
    for (size_t i = 0; i < flat.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            const int n = (c + 1) % 3;
            const uint32_t a = flat[i].vertex[c], b = flat[i].vertex[n];
            const double third = side_of(flat[i].x[c], flat[i].y[c], flat[i].x[n], flat[i].y[n], flat[i].x[3 - c - n],
                                         flat[i].y[3 - c - n]);
            int sharing = 0;
            bool opposite = false;
            for (size_t j = 0; j < flat.size(); ++j) {
                if (j == i) continue;
                for (int k = 0; k < 3; ++k) {
                    const int m = (k + 1) % 3;
                    if (!((flat[j].vertex[k] == a && flat[j].vertex[m] == b) ||
                          (flat[j].vertex[k] == b && flat[j].vertex[m] == a)))
                        continue;
                    ++sharing;
                    const double other = side_of(flat[i].x[c], flat[i].y[c], flat[i].x[n], flat[i].y[n],
                                                 flat[j].x[3 - k - m], flat[j].y[3 - k - m]);
                    opposite = (third > 0.0 && other < 0.0) || (third < 0.0 && other > 0.0);
                }
            }
            if (sharing == 1 && opposite) continue;  // inside the union
            nearest = std::min(nearest, origin_segment_distance(flat[i].x[c], flat[i].y[c], flat[i].x[n], flat[i].y[n]));
        }
    out.certain = nearest > slack;
    // The farthest a nearby ray's first crossing may lie: where one triangle covers every such
    // ray, its t; else (near an inner edge) the farthest triangle within reach.
    out.t_far = std::isfinite(t_covering) ? t_covering : t_reach;
    out.slack_t = slack / along;
    return out;
}

bool RoundingArbiter::certain(const Ray& ray, uint32_t prim) const { return certainty(ray, prim).certain; }

bool RoundingArbiter::skipped_certain_hit(const Ray& ray, const Hit& nearer, const Hit& other) const {
    if (!nearer.found() || nearer.prim == other.prim || (other.found() && !(nearer.t < other.t))) return false;
    const Certainty c = certainty(ray, nearer.prim);
    return c.certain && (!other.found() || double(other.t) > c.t_far + c.slack_t);
}

bool RoundingArbiter::candidate_within_rounding(const Ray& ray, const Hit& reference, const Hit& candidate) const {
    if ((reference.found() && !triangle(reference.prim)) || (candidate.found() && !triangle(candidate.prim)))
        return false;
    if (candidate.found() && !possible(ray, candidate)) return false;
    // An impossible reference hit (a transform ignored, a t far off) is no rounding either.
    if (reference.found() && !possible(ray, reference)) return false;
    // Either side may have skipped the other's nearer hit: rounding explains that only when some
    // ray within rounding of this one misses it and everything around it in the mesh. A candidate
    // that finds a certain hit the reference missed still disagrees (the reference is then the
    // wrong one, which the report must show too).
    return !skipped_certain_hit(ray, reference, candidate) && !skipped_certain_hit(ray, candidate, reference);
}

bool RoundingArbiter::occlusion_within_rounding(const Ray& ray, bool candidate_occluded, const Hit& reference_closest,
                                                const Hit& candidate_closest) const {
    for (const Hit* h : {&reference_closest, &candidate_closest})
        if (h->found() && !triangle(h->prim)) return false;  // shapes: no exact test here
    if (!candidate_occluded) {
        // The candidate's any-hit path saw nothing: right only if no occluder either structure's
        // closest hit names is certain (its own closest hit counts: the any-hit path alone may be
        // what is wrong).
        for (const Hit* h : {&reference_closest, &candidate_closest})
            if (h->found() && certain(ray, h->prim)) return false;
        return true;
    }
    // The candidate's any-hit path saw an occluder the reference's did not: its closest hit must
    // name one, possible within the interval and not certain (else the reference missed it).
    return candidate_closest.found() && possible(ray, candidate_closest) && !certain(ray, candidate_closest.prim);
}

}  // namespace thicket
