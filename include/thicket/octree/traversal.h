#pragma once
/// Octree traversals, both front to back along the ray:
/// - parametric (Revelles, Ureña & Lastra 2000): top-down, from the distances t0, t1 to each
///   cell's entry and exit planes and tm to its mid-planes; the first child from the entry plane,
///   the next from the smallest child exit (the paper's state table). Negative directions are
///   handled by the paper's mirroring: children are numbered in the ray's travel order and the
///   index is XOR-ed with `flip` (their `a`), without mirroring any coordinate.
/// - restart (the lecture; Glassner 1984): locate the leaf containing the ray's point at the
///   current t by descending from the root, test it, continue at the leaf's exit distance.
///   Location compares t with the mid-plane distances, so the leaf after an exit is the one the
///   ray enters there, with no epsilon nudge (ties go forward).
/// Every distance to a plane is the product plane_distance() forms, and cells share the exact
/// plane floats (octree_mid), so both traversals and the builder agree on every boundary.
///
/// A primitive referenced by several cells may be hit outside the cell being visited: the hit is
/// kept (it is real) and mailboxing stops it being tested twice, but the query ends only once the
/// closest hit so far lies within the current leaf's exit distance; every later cell is entered at
/// or beyond that distance, so nothing closer can follow. Cells are skipped only by widened
/// distances (entry beyond the search interval by more than the box tests' slack).
#include <algorithm>
#include <cmath>

#include "thicket/core/hit_query.h"
#include "thicket/core/mailbox.h"
#include "thicket/core/slab_interval.h"
#include "thicket/octree/node.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {

enum class OctreeTraversal { Parametric, Restart };

namespace octree_detail {

/// Per axis, the distances to a cell's planes in the ray's travel order: t0 where the ray enters
/// the slab, t1 where it leaves. For a ray parallel to the axis they are -inf, +inf inside the
/// slab and equal infinities outside; a ray lying in a face plane counts as inside.
struct Planes {
    float t0[3], t1[3];

    // The distances are never NaN (see Query::enter_distance), so plain comparisons do.
    float enter() const { return std::max(t0[0], std::max(t0[1], t0[2])); }
    float exit() const { return std::min(t1[0], std::min(t1[1], t1[2])); }
};

/// Closest hit (AnyHit = false: updates `hit`) or any hit (AnyHit = true: returns at the first
/// primitive hit within [tmin, tmax]).
template <bool AnyHit, class Prims, class C>
struct Query : QueryState<AnyHit, OctreeData, Prims, C> {
    using State = QueryState<AnyHit, OctreeData, Prims, C>;
    using State::data, State::prims, State::ray, State::hit, State::counters, State::far;
    const RayBoxQuery q;
    Mailbox mailbox;
    int flip = 0;  ///< bit a set when the ray runs towards -a: travel-order child m is child m ^ flip
    bool occluded = false;  ///< any-hit: a primitive was hit

    Query(const OctreeData& t, const Prims& p, const Ray& r, Hit& h, C& c)
        : State(t, p, r, h, c), q(r), mailbox(p.size()) {
        for (int a = 0; a < 3; ++a) flip |= q.neg[a] << a;
    }

    /// Distance to the plane the ray meets first (entering) or last (leaving) on one axis of box.
    float enter_distance(const Aabb& box, int a) const {
        const float t = plane_distance(q, a, q.neg[a] ? box.max[a] : box.min[a]);
        return std::isnan(t) ? -kInfinity : t;  // lying in the face: inside the closed slab
    }
    float exit_distance(const Aabb& box, int a) const {
        const float t = plane_distance(q, a, q.neg[a] ? box.min[a] : box.max[a]);
        return std::isnan(t) ? kInfinity : t;
    }
    /// Distance to a cell's mid-plane on axis a; a ray lying in it stays in the first half.
    float mid_distance(const Aabb& box, int a) const {
        const float t = plane_distance(q, a, octree_mid(box.min[a], box.max[a]));
        return std::isnan(t) ? kInfinity : t;
    }

    Planes planes(const Aabb& box) const {
        Planes p;
        for (int a = 0; a < 3; ++a) {
            p.t0[a] = enter_distance(box, a);
            p.t1[a] = exit_distance(box, a);
        }
        return p;
    }

    /// Whether the ray reaches the root cell within its search interval (widened like the box
    /// tests, so a hit exactly on the root's boundary is not lost).
    bool reaches_root(const Planes& root) const {
        const float t0 = widen_near(root.enter()), t1 = widen_far(root.exit());
        return t0 <= t1 && t0 <= far() && t1 >= ray.tmin;
    }

    /// Tests a leaf's primitives, each at most once per query. True ends the query: any-hit found
    /// something, or the closest hit so far lies within this leaf's exit distance.
    bool leaf(const OctreeNode& node, float exit) {
        // Tests may count leaves with a counters type that has leaf(node index).
        if constexpr (requires { counters.leaf(uint32_t{}); }) counters.leaf(uint32_t(&node - data.nodes.data()));
        if (this->test_prims(data.refs, node.index, node.index + node.count,
                             [&](uint32_t p) { return mailbox.first_visit(p); }))
            return occluded = true;
        return !AnyHit && hit.found() && hit.t <= exit;
    }

    /// Revelles' proc_subtree on node n with cell `box` and plane distances p. True ends the query.
    bool parametric(uint32_t n, const Aabb& box, const Planes& p) {
        const float enter = p.enter(), exit = p.exit();
        // Children come in the order the ray enters them: once one starts beyond the search
        // interval, so does everything after it.
        if (widen_near(enter) > far()) return true;
        if (widen_far(exit) < ray.tmin) return false;
        counters.node();
        const OctreeNode& node = data.nodes[n];
        if (node.is_leaf()) return leaf(node, exit);
        float tm[3];
        for (int a = 0; a < 3; ++a) tm[a] = mid_distance(box, a);
        // First child: past the mid-plane on every axis whose mid-plane lies before the entry.
        int m = 0;
        for (int a = 0; a < 3; ++a) m |= (tm[a] < enter) << a;
        while (true) {
            Planes child;
            for (int a = 0; a < 3; ++a) {
                const bool second = (m >> a) & 1;
                child.t0[a] = second ? tm[a] : p.t0[a];
                child.t1[a] = second ? p.t1[a] : tm[a];
            }
            const int c = m ^ flip;
            if (parametric(node.index + uint32_t(c), octree_child_box(box, c), child)) return true;
            // Next child: across the plane the ray leaves this child by; leaving through one of
            // the cell's own planes ends the cell.
            int axis = 0;
            for (int a = 1; a < 3; ++a)
                if (child.t1[a] < child.t1[axis]) axis = a;
            if ((m >> axis) & 1) return false;
            m |= 1 << axis;
        }
    }

    /// Descends from the root to the leaf whose cell the ray is in at distance t (on a
    /// mid-plane: the half the ray goes into); returns its node index and sets `box`.
    uint32_t locate(float t, Aabb& box) {
        uint32_t n = 0;
        box = data.root;
        counters.node();
        while (!data.nodes[n].is_leaf()) {
            int c = 0;
            for (int a = 0; a < 3; ++a) {
                const float mid = octree_mid(box.min[a], box.max[a]);
                const bool second = mid_distance(box, a) <= t;  // in travel order
                const bool upper = second != (q.neg[a] != 0);
                c |= int(upper) << a;
                (upper ? box.min : box.max)[a] = mid;
            }
            n = data.nodes[n].index + uint32_t(c);
            counters.node();
        }
        return n;
    }

    /// The lecture's restart traversal. True ends the query.
    bool restart(const Planes& root) {
        const float root_exit = root.exit();
        float t = std::fmax(ray.tmin, root.enter());
        while (true) {
            Aabb box;
            const uint32_t n = locate(t, box);
            const float exit = planes(box).exit();
            if (leaf(data.nodes[n], exit)) return true;
            if (!(exit < root_exit)) return false;  // left the root (NaN: a broken ray, stop)
            // A cell of zero length along the ray (planes whose distances round to the same
            // float) gives no progress: step to the next float instead.
            t = exit > t ? exit : std::nextafter(t, kInfinity);
            if (t > root_exit || widen_near(t) > far()) return false;
        }
    }

    /// Runs the query; returns whether any-hit found something.
    bool run(OctreeTraversal traversal) {
        if (data.nodes.empty()) return false;
        const Planes root = planes(data.root);
        if (!reaches_root(root)) return false;
        if (traversal == OctreeTraversal::Restart)
            restart(root);
        else
            parametric(0, data.root, root);
        return occluded;
    }
};

}  // namespace octree_detail

}  // namespace thicket
