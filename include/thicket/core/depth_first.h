#pragma once
/// The one explicit-stack walk over a tree that drawings, figures and validators share: each
/// item is visited once, and the visit schedules the children it wants walked.
#include <cstdint>
#include <utility>
#include <vector>

#include "thicket/core/aabb.h"

namespace thicket {

/// A node and its depth from the root.
struct NodeAtDepth {
    uint32_t node = 0, depth = 0;
};
/// A node, its depth and the box it covers (a cell the tree's nodes do not store).
struct NodeInBox {
    uint32_t node = 0, depth = 0;
    Aabb box;
};

/// Calls visit(item, stack) for `root` and for every item pushed onto `stack` (a
/// std::vector<Item>&) by a visit, last pushed first: push the right child before the left one
/// to walk left first. No recursion, so a deep (validated) tree costs a vector, not the C stack.
template <class Item, class Visit>
void depth_first(Item root, Visit&& visit) {
    std::vector<Item> stack{std::move(root)};
    while (!stack.empty()) {
        const Item item = std::move(stack.back());
        stack.pop_back();
        visit(item, stack);
    }
}

}  // namespace thicket
