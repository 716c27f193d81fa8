#pragma once
/// kD-tree traversals: the classic near/far stack traversal (Havran's TA_rec_B, as in pbrt) and
/// kd-restart (Foley & Sugerman 2005: no stack; descend from the root for each interval
/// [t, t_exit] and move t to the leaf's exit).
///
/// Robustness, shared by both:
/// - A split plane's crossing distance (split - o) * (1/d) is within gamma(3) of the exact one,
///   so each child is visited over its interval widened by twice that (kSplitSlack): no cell the
///   exact ray touches is ever skipped, whatever the order in which rounding puts two nearly
///   simultaneous crossings, and cells the ray crosses at a single point (flat cells, edges and
///   corners) are visited.
/// - A direction component of +0 or -0 never yields 0 * inf: the ray's coordinate on that axis
///   is exactly the origin's, so it is on one side, or lies in the plane and visits both sides.
/// - A hit found in a cell is kept even when it lies beyond the cell's exit (the primitive reaches
///   into later cells); the query only ends once every cell left starts beyond the hit, with the
///   entry widened by kSlabSlack like every box test, since a primitive's reported t may be that
///   far from its true point.
/// - kd-restart alone visits only the leaves whose exact interval has positive length. Where a
///   plane is crossed within rounding of the current leaf's ends, or the ray lies in a split
///   plane, the other side is searched with the stack walk restricted to the leaves the restart
///   never reaches (those are rare: the common path is the plain restart).
/// Primitives referenced by several leaves are tested once per query (Mailbox).
#include <cmath>

#include "thicket/core/hit_query.h"
#include "thicket/core/mailbox.h"
#include "thicket/core/ray_box.h"
#include "thicket/kdtree/node.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {

enum class KdTraversal { Restart, Stack };

namespace kd_detail {

inline constexpr float kSplitSlack = 2.0f * rounding_gamma(3);

/// The crossing distance `t` widened towards -inf / +inf (infinities stay infinite).
inline float lower(float t) { return t * (t > 0.0f ? 1.0f - kSplitSlack : 1.0f + kSplitSlack); }
inline float upper(float t) { return t * (t > 0.0f ? 1.0f + kSplitSlack : 1.0f - kSplitSlack); }

/// Whether a cell entered at `entry` lies wholly beyond a hit at distance `t`.
inline bool beyond(float entry, float t) { return entry > t + std::fabs(t) * kSlabSlack; }

/// The ray's interval [t0, t1] through `box` within [ray.tmin, ray.tmax], widened like the slab
/// test of ray_box.h (whose entry it uses); false if the ray misses the box.
inline bool root_interval(const Ray& ray, const Aabb& box, float& t0, float& t1) {
    const RayBoxQuery q(ray);
    t0 = ray_box_entry(q, box, ray.tmin, ray.tmax);
    if (t0 == kInfinity) return false;
    constexpr float grow = 1.0f + 2.0f * rounding_gamma(3) + kSlabSlack;
    constexpr float shrink = 1.0f - 2.0f * rounding_gamma(3) - kSlabSlack;
    t1 = ray.tmax;
    for (int a = 0; a < 3; ++a) {
        float far_t = ((q.neg[a] ? box.min : box.max)[a] - q.org[a]) * q.inv_dir[a];
        far_t *= far_t > 0.0f ? grow : shrink;
        t1 = far_t < t1 ? far_t : t1;  // NaN (origin in a face, parallel) does not narrow
    }
    return t0 <= t1;
}

/// What the ray does at an interior node.
struct Step {
    enum Kind { Cross, Parallel, InPlane };
    uint32_t first;   ///< Cross: the child met first; Parallel: the child holding the ray; InPlane: below
    uint32_t second;  ///< Cross: the child met second; InPlane: above
    float t;          ///< Cross: distance at which the plane is crossed
    Kind kind;
};

/// Closest hit (AnyHit = false: updates `hit`) or any hit (AnyHit = true: returns true at the
/// first primitive hit within [tmin, tmax]).
template <bool AnyHit, class Prims, class C>
struct KdQuery : QueryState<AnyHit, KdTreeData, Prims, C> {
    using State = QueryState<AnyHit, KdTreeData, Prims, C>;
    using State::data, State::ray, State::hit, State::counters, State::far, State::test_prims;
    Mailbox mailbox;
    Vec3 inv;

    KdQuery(const KdTreeData& t, const Prims& p, const Ray& r, Hit& h, C& c)
        : State(t, p, r, h, c), mailbox(p.size()), inv(1.0f / r.dir.x, 1.0f / r.dir.y, 1.0f / r.dir.z) {}

    Step step(uint32_t n, const KdNode& node) const {
        const int a = node.axis();
        const float split = node.split(), o = ray.org[a], d = ray.dir[a];
        const uint32_t below = n + 1, above = node.above();
        if (d == 0.0f) {  // +0 or -0: the ray's coordinate on this axis is exactly o
            if (o < split) return {below, above, 0.0f, Step::Parallel};
            if (o > split) return {above, below, 0.0f, Step::Parallel};
            return {below, above, 0.0f, Step::InPlane};
        }
        float t = (split - o) * inv[a];
        if (t != t) t = 0.0f;  // 1/d overflowed for a tiny d and the origin lies in the plane
        return d > 0.0f ? Step{below, above, t, Step::Cross} : Step{above, below, t, Step::Cross};
    }

    /// Tests a leaf's primitives (each once per query); true ends the query (any-hit found one).
    bool leaf(const KdNode& node) {
        return test_prims(data.prim_indices, node.first(), node.first() + node.count(),
                          [&](uint32_t p) { return mailbox.first_visit(p); });
    }

    /// Near/far stack traversal of the subtree at `n` over [t0, t1] (widened intervals). With
    /// Exact, [x0, x1] carries each node's unwidened interval as kd-restart computes it, and only
    /// leaves whose exact interval is empty are tested: the restart visits the others itself.
    template <bool Exact>
    bool walk(uint32_t n, float t0, float t1, float x0 = 0.0f, float x1 = 0.0f) {
        struct Entry {
            uint32_t node;
            float t0, t1, x0, x1;
        };
        Entry stack[kKdStackSize];
        uint32_t sp = 0;
        while (true) {
            bool reached_leaf = true;
            KdNode node;
            while (true) {
                counters.node();
                node = data.nodes[n];
                if (node.is_leaf()) break;
                const Step s = step(n, node);
                if (s.kind == Step::Parallel) {
                    n = s.first;
                    continue;
                }
                if (s.kind == Step::InPlane) {  // both sides hold the ray; the restart never goes above
                    stack[sp++] = {s.second, t0, t1, kInfinity, -kInfinity};
                    n = s.first;
                    continue;
                }
                const float lo = lower(s.t), hi = upper(s.t);
                const float first_t1 = hi < t1 ? hi : t1;
                const float second_t0 = lo > t0 ? lo : t0;
                const bool want_first = t0 <= hi;
                const bool want_second = second_t0 <= t1 && !beyond(second_t0, far());
                float split_x0 = 0.0f, split_x1 = 0.0f;
                if constexpr (Exact) {
                    split_x0 = s.t > x0 ? s.t : x0;
                    split_x1 = s.t < x1 ? s.t : x1;
                }
                if (want_first) {
                    if (want_second) stack[sp++] = {s.second, second_t0, t1, split_x0, x1};
                    n = s.first;
                    t1 = first_t1;
                    x1 = split_x1;
                } else if (want_second) {
                    n = s.second;
                    t0 = second_t0;
                    x0 = split_x0;
                } else {
                    reached_leaf = false;
                    break;
                }
            }
            if (reached_leaf && (!Exact || !(x0 < x1)) && leaf(node)) return true;
            while (true) {
                if (sp == 0) return false;
                const Entry& e = stack[--sp];
                if (beyond(e.t0, far())) continue;
                n = e.node;
                t0 = e.t0;
                t1 = e.t1;
                x0 = e.x0;
                x1 = e.x1;
                break;
            }
        }
    }

    /// kd-restart over [t_begin, t_end]: each pass descends from the root to the leaf holding
    /// the current t (a plane crossed exactly at t counts as behind), tests it and moves t to
    /// the leaf's exit. Exact decisions make t strictly increase, so the passes end.
    bool restart(float t_begin, float t_end) {
        enum Kind : uint8_t { kBehind, kAhead, kInPlane };
        struct Side {  // a child the pass did not take, in case rounding makes it matter
            uint32_t node;
            Kind kind;
            float t;       ///< crossing distance of its parent's plane
            float w0, w1;  ///< its widened interval
            float x0, x1;  ///< its exact interval
        };
        Side sides[kKdStackSize];
        float t = t_begin;
        for (bool first_pass = true;; first_pass = false) {
            uint32_t n = 0, ns = 0;
            float x0 = t_begin, x1 = t_end;  // the exact interval of node n
            KdNode node;
            while (true) {
                counters.node();
                node = data.nodes[n];
                if (node.is_leaf()) break;
                const Step s = step(n, node);
                if (s.kind == Step::Parallel) {
                    n = s.first;
                } else if (s.kind == Step::InPlane) {
                    sides[ns++] = {s.second, kInPlane, 0.0f, lower(x0), upper(x1), kInfinity, -kInfinity};
                    n = s.first;
                } else if (s.t > t) {  // t lies before the plane: first side now, second in a later pass
                    const float sx0 = s.t > x0 ? s.t : x0;
                    sides[ns++] = {s.second, kAhead, s.t, lower(sx0), upper(x1), sx0, x1};
                    x1 = s.t < x1 ? s.t : x1;
                    n = s.first;
                } else {  // the plane is behind t: second side
                    const float fx1 = s.t < x1 ? s.t : x1;
                    if (upper(fx1) >= lower(t)) sides[ns++] = {s.first, kBehind, s.t, lower(x0), upper(fx1), x0, fx1};
                    x0 = s.t > x0 ? s.t : x0;
                    n = s.second;
                }
            }
            const float exit = x1;
            if (leaf(node)) return true;
            // Search the sides that may hold leaves the passes never reach near [t, exit]. The
            // side the previous pass came from (the topmost plane crossed exactly at t) and the
            // one the next pass goes to (the topmost plane crossed exactly at exit) are the
            // neighbours' business: they search around their own ends.
            const float r0 = lower(t), r1 = upper(exit);
            bool skip_behind = !first_pass, skip_ahead = exit < t_end;
            for (uint32_t i = 0; i < ns; ++i) {
                const Side& s = sides[i];
                if (s.kind == kBehind && skip_behind && s.t == t) {
                    skip_behind = false;
                    continue;
                }
                if (s.kind == kAhead && skip_ahead && s.t == exit) {
                    skip_ahead = false;
                    continue;
                }
                const float w0 = s.w0 > r0 ? s.w0 : r0, w1 = s.w1 < r1 ? s.w1 : r1;
                if (w0 <= w1 && !beyond(w0, far()) && walk<true>(s.node, w0, w1, s.x0, s.x1)) return true;
            }
            if (!(exit < t_end) || beyond(lower(exit), far())) return false;
            t = exit;
        }
    }

    bool run(KdTraversal traversal) {
        float t0, t1;
        if (data.nodes.empty() || !root_interval(ray, data.bounds, t0, t1)) return false;
        return traversal == KdTraversal::Restart ? restart(t0, t1) : walk<false>(0, t0, t1);
    }
};

}  // namespace kd_detail

}  // namespace thicket
