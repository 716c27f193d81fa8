#pragma once
/// One walk for the figures every tree reports (nodes, leaves, depth, largest leaf, SAH cost),
/// so that the BVH, BIH, BSP, octree and kD-tree compute them the same way, and one copy of
/// those figures into AccelStats' shared fields.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/depth_first.h"
#include "thicket/core/sah.h"

namespace thicket {

/// Figures of a tree's shape and SAH cost (kSahTraversalCost per interior node, kSahIntersectionCost
/// per primitive reference in a leaf, each weighted by its box's area relative to the root's).
struct TreeFigures {
    size_t nodes = 0, leaves = 0, empty_leaves = 0, max_depth = 0, max_leaf_size = 0;
    size_t references = 0;  ///< primitive references summed over the leaves
    double sah_cost = 0.0;
};

/// A node on the walk: its index, depth (root 0) and box.
using TreeWalkItem = NodeInBox;

/// Walks the tree depth-first from node 0 with box `root_box`. For each node,
/// `expand(item, rel, push)` returns the leaf's primitive count for a leaf, or std::nullopt for
/// an interior node after calling push(child) for each child (the last pushed is visited first);
/// `rel` is the node's area relative to the root's (1 for every node of a flat root). An empty
/// tree (`has_nodes` false) has zero figures.
template <class Expand>
TreeFigures walk_tree(bool has_nodes, const Aabb& root_box, Expand&& expand) {
    TreeFigures f;
    if (!has_nodes) return f;
    const float root_area = root_box.half_area();
    depth_first(TreeWalkItem{0, 0, root_box}, [&](const TreeWalkItem& item, std::vector<TreeWalkItem>& stack) {
        auto push = [&stack](const TreeWalkItem& child) { stack.push_back(child); };
        // A degenerate (flat or point-sized) root weighs every node equally.
        const double rel = root_area > 0.0f ? double(item.box.half_area()) / root_area : 1.0;
        ++f.nodes;
        f.max_depth = std::max<size_t>(f.max_depth, item.depth);
        const std::optional<size_t> leaf = expand(item, rel, push);
        if (leaf) {
            ++f.leaves;
            f.empty_leaves += *leaf == 0;
            f.references += *leaf;
            f.max_leaf_size = std::max(f.max_leaf_size, *leaf);
            f.sah_cost += rel * kSahIntersectionCost * double(*leaf);
        } else {
            f.sah_cost += rel * kSahTraversalCost;
        }
    });
    return f;
}

}  // namespace thicket
