#pragma once
/// BVH traversals of the lecture: recursive (as on the slide), iterative with a stack, and
/// ordered traversal by each of the three ways to pick the near child. All of them skip nodes
/// the ray enters beyond the current hit distance (early out), and every node whose box is
/// tested counts as visited.
#include <utility>

#include "thicket/bvh/node.h"
#include "thicket/core/hit_query.h"
#include "thicket/core/ordered_traversal.h"
#include "thicket/core/ray_box.h"
#include "thicket/core/traversal_record.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {

enum class BvhTraversal { Recursive, Stack, OrderedDistance, OrderedAxis, OrderedCentroid };

namespace bvh_detail {

/// Closest hit (AnyHit = false: updates `hit`, returns whether anything was hit) or any hit
/// (AnyHit = true: returns at the first primitive hit within [tmin, tmax]). Data is BvhData, or
/// BvhDataD for the double BVH (the same tree with double boxes, traced with double rays).
template <bool AnyHit, class Prims, class C, class Data>
struct QueryOver : QueryState<AnyHit, Data, Prims, C, /*Records=*/true, typename Data::Scalar> {
    using S = typename Data::Scalar;
    using Node = typename Data::Node;
    using State = QueryState<AnyHit, Data, Prims, C, true, S>;
    using State::data, State::ray, State::counters, State::far, State::test_prims;
    const RayBoxQueryT<S> box;

    QueryOver(const Data& b, const Prims& p, const RayT<S>& r, HitT<S>& h, C& c) : State(b, p, r, h, c), box(r) {}

    S enter(uint32_t n) {
        counters.node();
        const S t = ray_box_entry(box, data.nodes[n].aabbMin, data.nodes[n].aabbMax, ray.tmin, far());
        if constexpr (RecordsSteps<C>) counters.record_node(n, t);
        return t;
    }

    /// Tests a leaf's primitives; true ends the query (any-hit found something).
    bool leaf(const Node& node) { return test_prims(data.prim_indices, node.leftFirst, node.leftFirst + node.count); }

    /// The slide's traversal: test the box, then the primitives or both children in order.
    bool recursive(uint32_t n) {
        if (enter(n) == kInfinity) return false;
        const Node& node = data.nodes[n];
        if (node.is_leaf()) return leaf(node);
        return recursive(node.leftFirst) || recursive(node.leftFirst + 1);
    }

    /// The same visiting order without recursion: boxes are tested when popped.
    bool stack() {
        uint32_t stack[kTraversalStackSize];
        uint32_t sp = 0;
        stack[sp++] = 0;
        while (sp > 0) {
            const uint32_t n = stack[--sp];
            if (enter(n) == kInfinity) continue;
            const Node& node = data.nodes[n];
            if (node.is_leaf()) {
                if (leaf(node)) return true;
            } else {
                stack[sp++] = node.leftFirst + 1;
                stack[sp++] = node.leftFirst;
            }
        }
        return false;
    }

    /// A pushed node dropped when popped (the hit found since is nearer): told to a recorder.
    void skipped(uint32_t n, S t_enter) {
        if constexpr (RecordsSteps<C>) counters.record_skip(n, t_enter);
    }

    bool is_leaf(uint32_t n) const { return data.nodes[n].is_leaf(); }
    uint32_t first_child(uint32_t n) const { return data.nodes[n].leftFirst; }
    bool leaf(uint32_t n) { return leaf(data.nodes[n]); }

    /// Ordered traversal (core/ordered_traversal.h) with the near child picked by entry
    /// distance, by the ray's sign along the split axis, or along the children's centroid axis.
    template <BvhTraversal Order>
    bool ordered() {
        return ordered_traversal<kTraversalStackSize>(*this, [&](uint32_t n, S t_first, S t_second) {
            if constexpr (Order == BvhTraversal::OrderedDistance) {
                return t_second < t_first;
            } else if constexpr (Order == BvhTraversal::OrderedAxis) {
                const uint8_t order = data.child_order[n];
                return (box.neg[ChildOrder::split_axis(order)] != 0) != ChildOrder::split_left_higher(order);
            } else {
                const uint8_t order = data.child_order[n];
                return (box.neg[ChildOrder::centroid_axis(order)] != 0) != ChildOrder::left_is_higher(order);
            }
        });
    }

    bool run(BvhTraversal traversal) {
        if (data.nodes_used == 0) return false;
        switch (traversal) {
        case BvhTraversal::Recursive: return recursive(0);
        case BvhTraversal::Stack: return stack();
        case BvhTraversal::OrderedDistance: return ordered<BvhTraversal::OrderedDistance>();
        case BvhTraversal::OrderedAxis: return ordered<BvhTraversal::OrderedAxis>();
        case BvhTraversal::OrderedCentroid: return ordered<BvhTraversal::OrderedCentroid>();
        }
        return false;
    }
};

/// The float BVH's query, with the three parameters closest_hit/any_hit take (a template with a
/// defaulted fourth parameter is not a template of three to clang 14).
template <bool AnyHit, class Prims, class C>
struct Query : QueryOver<AnyHit, Prims, C, BvhData> {
    using QueryOver<AnyHit, Prims, C, BvhData>::QueryOver;
};

}  // namespace bvh_detail

}  // namespace thicket
