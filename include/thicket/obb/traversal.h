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
struct Query : QueryState<AnyHit, ObbData, Prims, C> {
    using State = QueryState<AnyHit, ObbData, Prims, C>;
    using State::State, State::data, State::ray, State::counters, State::far, State::test_prims;

    /// Entry distance of node n's box within [tmin, far()], or +inf when missed.
    float enter(uint32_t n) {
        counters.node();
        const ObbNode& b = data.nodes[n];
        const Vec3 v = ray.org - b.center;
        Ray local;
        local.org = {dot(b.axis[0], v), dot(b.axis[1], v), dot(b.axis[2], v)};
        local.dir = {dot(b.axis[0], ray.dir), dot(b.axis[1], ray.dir), dot(b.axis[2], ray.dir)};
        return ray_box_entry(RayBoxQuery(local), -b.half, b.half, ray.tmin, far());
    }

    /// Tests a leaf's primitives; true ends the query (any-hit found something).
    bool leaf(const ObbNode& node) { return test_prims(data.prim_indices, node.leftFirst, node.leftFirst + node.count); }

    bool is_leaf(uint32_t n) const { return data.nodes[n].is_leaf(); }
    uint32_t first_child(uint32_t n) const { return data.nodes[n].leftFirst; }
    bool leaf(uint32_t n) { return leaf(data.nodes[n]); }

    /// Ordered traversal (core/ordered_traversal.h), the nearer child by entry distance first.
    bool run() {
        if (data.nodes.empty()) return false;
        return ordered_traversal<kObbStackSize>(*this, [](uint32_t, float t_first, float t_second) { return t_second < t_first; });
    }
};

}  // namespace obb_detail

}  // namespace thicket
