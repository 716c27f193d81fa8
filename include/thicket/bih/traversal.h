#pragma once
/// BIH traversal (Wächter & Keller 2006): kd-tree style. The ray's interval [tnear, tfar] is
/// clipped against both planes of a node: the near child gets [tnear, min(tfar, t_near_plane)],
/// the far child [max(tnear, t_far_plane), tfar]; either may be empty (the ray passes through a
/// gap between the children) and both may be visited (the children overlap). The near child is
/// visited first, the far one is pushed with its interval and skipped when popped if a hit
/// closer than its entry has been found meanwhile. Children are ordered by the ray's sign on the
/// split axis, like the planes of the slab test, so +0 and -0 components are consistent.
#include "thicket/bih/node.h"
#include "thicket/core/hit_query.h"
#include "thicket/core/slab_interval.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {

namespace bih_detail {

/// Closest hit (AnyHit = false: updates `hit`) or any hit (AnyHit = true: returns at the first
/// primitive hit within [tmin, tmax]).
template <bool AnyHit, class Prims, class C>
struct Query : QueryState<AnyHit, BihData, Prims, C> {
    using State = QueryState<AnyHit, BihData, Prims, C>;
    using State::data, State::ray, State::counters, State::far, State::test_prims;
    const RayBoxQuery q;

    Query(const BihData& b, const Prims& p, const Ray& r, Hit& h, C& c) : State(b, p, r, h, c), q(r) {}

    /// Tests a leaf's primitives; true ends the query (any-hit found something).
    bool leaf(const BihNode& node) { return test_prims(data.prim_indices, node.index(), node.index() + node.count()); }

    bool run() {
        if (data.nodes.empty()) return false;
        const SlabInterval root = ray_box_interval(q, data.bounds, ray.tmin, far());
        if (root.empty()) return false;
        struct Entry {
            uint32_t node;
            float tnear, tfar;
        };
        Entry stack[kBihStackSize];
        uint32_t sp = 0;
        uint32_t n = 0;
        float tnear = root.t0, tfar = root.t1;
        while (true) {
            counters.node();
            const BihNode& node = data.nodes[n];
            if (node.is_leaf()) {
                if (leaf(node)) return true;
            } else {
                const int a = node.axis();
                // A primitive's accepted hits lie on its side of the widened plane distance
                // (see slab_interval.h); NaN (the ray lies in the plane) narrows nothing.
                const float t_left = plane_distance(q, a, node.left_max());
                const float t_right = plane_distance(q, a, node.right_min());
                const bool left_first = q.neg[a] == 0;
                const float t_near_plane = widen_far(left_first ? t_left : t_right);
                const float t_far_plane = widen_near(left_first ? t_right : t_left);
                const uint32_t near_child = node.index() + (left_first ? 0 : 1);
                const uint32_t far_child = node.index() + (left_first ? 1 : 0);
                const float near_end = t_near_plane < tfar ? t_near_plane : tfar;
                const float far_begin = t_far_plane > tnear ? t_far_plane : tnear;
                const bool visit_near = tnear <= near_end, visit_far = far_begin <= tfar;
                if (visit_near) {
                    if (visit_far) stack[sp++] = {far_child, far_begin, tfar};
                    n = near_child;
                    tfar = near_end;
                    continue;
                }
                if (visit_far) {
                    n = far_child;
                    tnear = far_begin;
                    continue;
                }
            }
            // Pop the next subtree the ray still reaches before the closest hit so far.
            while (true) {
                if (sp == 0) return false;
                const Entry e = stack[--sp];
                if (e.tnear <= far()) {
                    n = e.node;
                    tnear = e.tnear;
                    tfar = e.tfar < far() ? e.tfar : far();
                    break;
                }
            }
        }
    }
};

}  // namespace bih_detail

}  // namespace thicket
