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
struct Query {
    const BihData& bih;
    const Prims& prims;
    const Ray& ray;
    const RayBoxQuery q;
    Hit& hit;
    C& counters;

    Query(const BihData& b, const Prims& p, const Ray& r, Hit& h, C& c) : bih(b), prims(p), ray(r), q(r), hit(h), counters(c) {}

    float far() const { return AnyHit ? ray.tmax : hit.t; }

    /// Tests a leaf's primitives; true ends the query (any-hit found something).
    bool leaf(const BihNode& node) {
        for (uint32_t i = node.index(), end = node.index() + node.count(); i < end; ++i) {
            counters.prim();
            if constexpr (AnyHit) {
                if (prims.occludes(bih.prim_indices[i], ray)) return true;
            } else {
                prims.intersect(bih.prim_indices[i], ray, hit);
            }
        }
        return false;
    }

    bool run() {
        if (bih.nodes.empty()) return false;
        const SlabInterval root = ray_box_interval(q, bih.bounds, ray.tmin, far());
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
            const BihNode& node = bih.nodes[n];
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
