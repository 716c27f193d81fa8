#pragma once
/// Near/far traversal of the BSP tree (Sung & Shirley): at each node the ray's interval
/// [t0, t1] is split where the ray crosses the plane; the near side (the one the ray starts in)
/// is visited first, the far side is pushed and visited only if it may hold a closer hit.
///
/// Robustness: the crossing t is computed in float, so each plane is widened into a band that
/// both sides accept: t_plane +- w with
///   w = 2 (E_d + |t_plane| E_n) / |n.d| + kSlabSlack |t_plane|,
///   E_d = kBspPlaneBand (|o| + 2 scale),  E_n = kBspPlaneBand |d|,
/// which bounds the rounding of n.o - offset and of n.d (|n| = 1, |offset| <= sqrt(3) scale),
/// the builder's in-plane tolerance, and the triangle tests' own t error (kSlabSlack, as for
/// boxes). A ray whose n.d is within 2 E_n of zero is parallel to the plane as far as float can
/// tell: it goes to the side its whole interval lies on, or to both sides over its whole interval
/// when it lies in the band (a ray in the plane). A hit exactly on a plane therefore lies inside
/// both sides' intervals and cannot be lost.
///
/// The hit-inside-the-cell rule: a hit found in a leaf may belong to a primitive that reaches
/// beyond the leaf's cell; it is kept (it is a real hit, and the test always runs on the original
/// primitive) and the traversal continues with the far sides still pushed, each skipped when its
/// widened entry lies beyond the hit. So traversal ends once the hit lies before every remaining
/// cell's entry, which is never later than "before the current leaf's widened exit".
#include <algorithm>
#include <cmath>

#include "thicket/bsp/node.h"
#include "thicket/core/hit_query.h"
#include "thicket/core/mailbox.h"
#include "thicket/core/ray_box.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {
namespace bsp_detail {

/// Closest hit (AnyHit = false: updates `hit`) or any hit (AnyHit = true: returns true at the
/// first primitive hit within [tmin, tmax]).
template <bool AnyHit, class Prims, class C>
bool query(const BspData& bsp, const Prims& prims, const Ray& ray, Hit& hit, C& counters) {
    if (bsp.nodes.empty()) return false;
    // The root cell is the scene's box: the slab test gives the entry, the same test on the
    // reversed ray the exit (both widened).
    const RayBoxQuery q(ray);
    float t0 = ray_box_entry(q, bsp.bounds, ray.tmin, ray.tmax);
    if (t0 == kInfinity) return false;
    RayBoxQuery reversed = q;
    for (int a = 0; a < 3; ++a) {
        reversed.inv_dir[a] = -q.inv_dir[a];
        reversed.neg[a] = 1 - q.neg[a];
    }
    float t1 = -ray_box_entry(reversed, bsp.bounds, -ray.tmax, -ray.tmin);
    if (!(t1 >= t0)) t1 = ray.tmax;  // rounding made the reversed test miss: keep the whole ray

    const float e_d = kBspPlaneBand * (length(ray.org) + 2.0f * bsp.scale);
    const float e_n = kBspPlaneBand * length(ray.dir);

    // A primitive cut into fragments is referenced by several leaves: test it once per query.
    Mailbox mailbox(prims.size());

    struct Entry {
        uint32_t node;
        float t0, t1;
    };
    Entry stack[kBspStackSize];
    uint32_t sp = 0;
    uint32_t n = 0;
    while (true) {
        const BspNode& node = bsp.nodes[n];
        counters.node();
        if (!node.is_leaf()) {
            const float denom = dot(node.plane.normal, ray.dir);
            const float dist = dot(node.plane.normal, ray.org) - node.plane.offset;
            const uint32_t back = node.index, front = node.index + 1;
            if (!(std::fabs(denom) > 2.0f * e_n)) {
                // Parallel to the plane within rounding: the distance to it changes by at most
                // (|n.d| + E_n) max|t| over the interval.
                const float reach = e_d + (std::fabs(denom) + e_n) * std::fmax(std::fabs(t0), std::fabs(t1));
                if (dist > reach) {
                    n = front;
                } else if (dist < -reach) {
                    n = back;
                } else {
                    stack[sp++] = {front, t0, t1};
                    n = back;
                }
                continue;
            }
            const float inv = 1.0f / denom;
            const float tp = -dist * inv;
            const float w = 2.0f * (e_d + std::fabs(tp) * e_n) * std::fabs(inv) + kSlabSlack * std::fabs(tp);
            const float lo = tp - w, hi = tp + w;
            const uint32_t near = denom > 0.0f ? back : front, far = denom > 0.0f ? front : back;
            const float far_end = AnyHit ? t1 : std::fmin(t1, hit.t);
            // Written so that a NaN bound visits (never culls) and never narrows the interval.
            const bool visit_near = !(t0 > hi), visit_far = !(lo > far_end);
            if (visit_near) {
                if (visit_far) stack[sp++] = {far, lo > t0 ? lo : t0, t1};
                n = near;
                t1 = hi < t1 ? hi : t1;
                continue;
            }
            if (visit_far) {
                n = far;
                t0 = lo > t0 ? lo : t0;
                continue;
            }
        } else {
            for (uint32_t i = node.index, end = node.index + node.leaf_size(); i < end; ++i) {
                const uint32_t prim = bsp.refs[i];
                if (!mailbox.first_visit(prim)) continue;
                counters.prim();
                if constexpr (AnyHit) {
                    if (prims.occludes(prim, ray)) return true;
                } else {
                    prims.intersect(prim, ray, hit);
                }
            }
        }
        // The next pushed far side that may still hold a closer hit.
        while (true) {
            if (sp == 0) return AnyHit ? false : hit.found();
            const Entry e = stack[--sp];
            if (AnyHit || e.t0 <= hit.t) {
                n = e.node;
                t0 = e.t0;
                t1 = e.t1;
                break;
            }
        }
    }
}

}  // namespace bsp_detail

namespace bsp_detail {

/// query() in the shape closest_hit()/any_hit() take.
template <bool AnyHit, class Prims, class C>
struct Query : QueryState<AnyHit, BspData, Prims, C> {
    using QueryState<AnyHit, BspData, Prims, C>::QueryState;
    bool run() const { return query<AnyHit>(this->data, this->prims, this->ray, this->hit, this->counters); }
};

}  // namespace bsp_detail

}  // namespace thicket
