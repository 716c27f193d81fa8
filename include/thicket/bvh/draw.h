#pragma once
/// The BVH's nodes as `thicket explore` draws them and recorded steps name them.
#include <functional>

#include "thicket/bvh/node.h"
#include "thicket/core/traversal_record.h"

namespace thicket {

/// Calls `visit` for every node reachable from the root (none for an empty BVH), parents before
/// children; NodeBox::id is the node-pool index the traversal records.
inline void bvh_for_each_node(const BvhData& bvh, const std::function<void(const NodeBox&)>& visit) {
    if (bvh.nodes_used == 0) return;
    struct Item {
        uint32_t node, depth;
    };
    std::vector<Item> stack{{0, 0}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const BvhNode& n = bvh.nodes[it.node];
        visit(NodeBox{it.node, it.depth, n.bounds(), n.is_leaf(), n.is_leaf() ? n.count : 0});
        if (!n.is_leaf()) {
            stack.push_back({n.leftFirst + 1, it.depth + 1});
            stack.push_back({n.leftFirst, it.depth + 1});
        }
    }
}

}  // namespace thicket
