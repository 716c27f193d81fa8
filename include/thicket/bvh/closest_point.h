#pragma once
/// The BVH's closest-point query: nearest child first, and a subtree whose box lies farther than
/// the best point so far is never opened.
#include "thicket/bvh/node.h"
#include "thicket/core/closest_point.h"

namespace thicket {

template <HasClosestPoint Prims>
NearestPoint bvh_closest_point(const BvhData& data, const Prims& prims, const Vec3& p) {
    constexpr double kBoxSlack = 1.0 + 1.0 / 65536.0;
    NearestPoint best;
    if (data.nodes_used == 0) return best;
    struct Entry {
        uint32_t node;
        double distance;  // from p to the node's box, a lower bound of everything inside (double: no overflow)
    };
    // Each step pops one entry and pushes at most two, so the stack holds at most depth + 1.
    Entry stack[kTraversalStackSize];
    int top = 0;
    stack[top++] = {0, std::sqrt(distance2_to_box(p, data.nodes[0].bounds()))};
    while (top > 0) {
        const Entry e = stack[--top];
        // The slack covers the box's and the triangle's distances rounding apart: a box holding a
        // triangle exactly as close as the best (a shared vertex, which the lower id wins) stays open.
        if (e.distance > double(best.distance) * kBoxSlack) continue;
        const BvhNode& node = data.nodes[e.node];
        if (node.is_leaf()) {
            for (uint32_t k = node.leftFirst; k < node.leftFirst + node.count; ++k) {
                const NearestPoint s = prims.closest_point(data.prim_indices[k], p);
                // Ties go to the lower id, as brute force's scan in id order gives them.
                if (s.distance < best.distance || (s.distance == best.distance && s.prim < best.prim)) best = s;
            }
            continue;
        }
        Entry a{node.leftFirst, std::sqrt(distance2_to_box(p, data.nodes[node.leftFirst].bounds()))};
        Entry b{node.leftFirst + 1, std::sqrt(distance2_to_box(p, data.nodes[node.leftFirst + 1].bounds()))};
        if (a.distance < b.distance) std::swap(a, b);
        stack[top++] = a;  // the farther one waits
        stack[top++] = b;
    }
    return best;
}

}  // namespace thicket
