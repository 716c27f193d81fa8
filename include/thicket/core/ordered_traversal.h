#pragma once
/// The ordered traversal of a binary tree of boxes (the lecture's "ordered traversal with early
/// out"), shared by the trees whose two children are siblings in the node pool: the BVH (axis-
/// aligned boxes) and the OBB tree (oriented boxes). What a box is, how a leaf is tested and
/// which child goes first are the tree's; the visiting order and the stack are here.
#include <cstdint>
#include <utility>

#include "thicket/core/ray.h"

namespace thicket {

/// Visits the tree from node 0 in order: both children's boxes are tested at the parent, the
/// near one is visited first, the far one is pushed with its entry distance and skipped when
/// popped if the query's far end has come closer than that distance meanwhile. `q` provides
///   float enter(uint32_t n)       entry distance of node n's box within the query's interval, or kInfinity;
///   bool is_leaf(uint32_t n), uint32_t first_child(uint32_t n)   (children are first and first + 1);
///   bool leaf(uint32_t n)         tests a leaf's primitives, true ends the query (any hit found);
///   float far()                   the query's current far end (the closest hit so far, or tmax);
/// and second_first(n, t_first, t_second) says whether node n's second child goes first;
/// optionally skipped(n, t): node n, pushed with entry t, is dropped as the query's far end came closer.
/// Returns true when a leaf ended the query. The tree must be at most StackSize deep.
template <uint32_t StackSize, class Query, class SecondFirst>
inline bool ordered_traversal(Query& q, SecondFirst&& second_first) {
    struct Entry {
        uint32_t node;
        decltype(q.far()) t;  // the query's scalar: float, or double for a double BVH
    };
    Entry stack[StackSize];
    uint32_t sp = 0;
    if (q.enter(0) == kInfinity) return false;
    uint32_t n = 0;
    while (true) {
        if (q.is_leaf(n)) {
            if (q.leaf(n)) return true;
        } else {
            uint32_t near = q.first_child(n), far_node = near + 1;
            auto t_near = q.enter(near), t_far = q.enter(far_node);
            if (second_first(n, t_near, t_far)) {
                std::swap(near, far_node);
                std::swap(t_near, t_far);
            }
            if (t_near != kInfinity) {
                if (t_far != kInfinity) stack[sp++] = {far_node, t_far};
                n = near;
                continue;
            }
            if (t_far != kInfinity) {
                n = far_node;
                continue;
            }
        }
        // Pop the next node still worth visiting.
        while (true) {
            if (sp == 0) return false;
            const Entry e = stack[--sp];
            if (e.t <= q.far()) {
                n = e.node;
                break;
            }
            // Only a query that records its steps has skipped() (core/traversal_record.h).
            if constexpr (requires { q.skipped(e.node, e.t); }) q.skipped(e.node, e.t);
        }
    }
}

}  // namespace thicket
