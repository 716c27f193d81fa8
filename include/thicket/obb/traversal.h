#pragma once
/// OBB tree traversal: ordered by entry distance with early out, the ray moved into each box's
/// frame and tested there with the robust slab test of the axis-aligned structures.
#include "thicket/core/hit_query.h"
#include "thicket/core/ordered_traversal.h"
#include "thicket/core/ray_box.h"
#include "thicket/obb/node.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {

namespace obb_detail {

/// Closest hit (AnyHit = false: narrows `hit`) or any hit (AnyHit = true: returns at the first
/// primitive hit within [tmin, tmax]); every box tested counts as a node visited.
template <bool AnyHit, class Prims, class C>
struct Query {
    const ObbData& obb;
    const Prims& prims;
    const Ray& ray;
    Hit& hit;
    C& counters;

    Query(const ObbData& o, const Prims& p, const Ray& r, Hit& h, C& c)
        : obb(o), prims(p), ray(r), hit(h), counters(c) {}

    float far() const { return AnyHit ? ray.tmax : hit.t; }

    /// Entry distance of node n's box within [tmin, far()], or +inf when missed.
    float enter(uint32_t n) {
        counters.node();
        const ObbNode& b = obb.nodes[n];
        const Vec3 v = ray.org - b.center;
        Ray local;
        local.org = {dot(b.axis[0], v), dot(b.axis[1], v), dot(b.axis[2], v)};
        local.dir = {dot(b.axis[0], ray.dir), dot(b.axis[1], ray.dir), dot(b.axis[2], ray.dir)};
        return ray_box_entry(RayBoxQuery(local), -b.half, b.half, ray.tmin, far());
    }

    /// Tests a leaf's primitives; true ends the query (any-hit found something).
    bool leaf(const ObbNode& node) {
        for (uint32_t i = node.leftFirst, end = node.leftFirst + node.count; i < end; ++i) {
            counters.prim();
            if constexpr (AnyHit) {
                if (prims.occludes(obb.prim_indices[i], ray)) return true;
            } else {
                prims.intersect(obb.prim_indices[i], ray, hit);
            }
        }
        return false;
    }

    bool is_leaf(uint32_t n) const { return obb.nodes[n].is_leaf(); }
    uint32_t first_child(uint32_t n) const { return obb.nodes[n].leftFirst; }
    bool leaf(uint32_t n) { return leaf(obb.nodes[n]); }

    /// Ordered traversal (core/ordered_traversal.h), the nearer child by entry distance first.
    bool run() {
        if (obb.nodes.empty()) return false;
        return ordered_traversal<kObbStackSize>(*this, [](uint32_t, float t_first, float t_second) { return t_second < t_first; });
    }
};

}  // namespace obb_detail

}  // namespace thicket
