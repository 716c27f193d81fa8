// Refit of the binary BVH: a backward sweep over the nodes the root reaches (children always
// follow their parent in the pool, validate_bvh), so each child's box is ready before its parent's.
#include "thicket/bvh/refit.h"

#include <cstdint>
#include <vector>

namespace thicket {

void refit_bvh(BvhData& bvh, std::span<const Aabb> prim_bounds) {
    if (bvh.nodes_used == 0) return;
    // Only reachable nodes: the pool may hold unused slots (slot 1, optimizer leftovers) whose
    // fields are not a valid node.
    std::vector<uint32_t> order{0};
    for (size_t k = 0; k < order.size(); ++k) {
        const BvhNode& node = bvh.nodes[order[k]];
        if (!node.is_leaf()) {
            order.push_back(node.leftFirst);
            order.push_back(node.leftFirst + 1);
        }
    }
    for (size_t k = order.size(); k-- > 0;) {
        BvhNode& node = bvh.nodes[order[k]];
        Aabb box;
        if (node.is_leaf()) {
            for (uint32_t e = node.leftFirst; e < node.leftFirst + node.count; ++e)
                box.grow(prim_bounds[bvh.prim_indices[e]]);
        } else {
            const Aabb left = bvh.nodes[node.leftFirst].bounds(), right = bvh.nodes[node.leftFirst + 1].bounds();
            box.grow(left);
            box.grow(right);
            // The ordered traversals' hints, recomputed as the build does (compute_child_order):
            // a mirror or a turn can put the left child on the higher side of its split axis.
            uint8_t& order_byte = bvh.child_order[order[k]];
            order_byte = ChildOrder::from_children(ChildOrder::split_axis(order_byte), left, right);
        }
        node.aabbMin = box.min;
        node.aabbMax = box.max;
    }
}

}  // namespace thicket
