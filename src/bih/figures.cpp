// Figures and structural checks of a built BIH. Node boxes are implicit: the root's box is the
// scene's bounds, a child's the parent's clipped by the child's plane on the split axis.
#include <algorithm>
#include <cmath>
#include <string>

#include "thicket/core/depth_first.h"
#include "thicket/bih/build.h"
#include "thicket/core/error.h"
#include "thicket/core/sah.h"

namespace thicket {

BihFigures bih_figures(const BihData& bih) {
    return walk_tree(!bih.nodes.empty(), bih.bounds,
                     [&](const TreeWalkItem& item, double, auto push) -> std::optional<size_t> {
                         const BihNode& node = bih.nodes[item.node];
                         if (node.is_leaf()) return node.count();
                         const int a = node.axis();
                         TreeWalkItem left{node.index(), item.depth + 1, item.box};
                         TreeWalkItem right{node.index() + 1, item.depth + 1, item.box};
                         left.box.max[a] = std::min(left.box.max[a], node.left_max());
                         right.box.min[a] = std::max(right.box.min[a], node.right_min());
                         // An empty child's plane lies beyond the box: its box is empty (area 0).
                         if (left.box.empty()) left.box = Aabb{};
                         if (right.box.empty()) right.box = Aabb{};
                         push(right);
                         push(left);
                         return std::nullopt;
                     });
}

void validate_bih(const BihData& bih, size_t primitive_count) {
    const size_t n = primitive_count;
    if (bih.prim_indices.size() != n)
        throw Error("invalid BIH: " + std::to_string(bih.prim_indices.size()) + " primitive indices for " +
                    std::to_string(n) + " primitives");
    if (n == 0) {
        if (!bih.nodes.empty()) throw Error("invalid BIH: nodes in a BIH over no primitives");
        return;
    }
    if (bih.nodes.empty() || bih.nodes.size() > 4 * n + 1 || bih.nodes.size() > kBihMaxIndex)
        throw Error("invalid BIH: " + std::to_string(bih.nodes.size()) + " nodes for " + std::to_string(n) +
                    " primitives");
    std::vector<uint8_t> referenced(n, 0);
    for (uint32_t idx : bih.prim_indices) {
        if (idx >= n || referenced[idx]) throw Error("invalid BIH: primitive index array is not a permutation");
        referenced[idx] = 1;
    }
    std::vector<uint8_t> node_seen(bih.nodes.size(), 0), entry_seen(n, 0);
    size_t covered = 0;
    depth_first(NodeAtDepth{0, 0}, [&](const NodeAtDepth& item, std::vector<NodeAtDepth>& stack) {
        const auto [i, depth] = item;
        const BihNode& node = bih.nodes[i];
        if (depth > kBihMaxDepth) throw Error("invalid BIH: deeper than " + std::to_string(kBihMaxDepth));
        if (node_seen[i]++) throw Error("invalid BIH: node " + std::to_string(i) + " has two parents");
        if (node.is_leaf()) {
            if (uint64_t(node.index()) + node.count() > n)
                throw Error("invalid BIH: leaf " + std::to_string(i) + " references primitives out of range");
            for (uint32_t e = node.index(); e < node.index() + node.count(); ++e)
                if (entry_seen[e]++) throw Error("invalid BIH: leaves overlap at primitive entry " + std::to_string(e));
            covered += node.count();
            return;
        }
        // Children always come after their parent: this rules out cycles.
        if (node.index() <= i || uint64_t(node.index()) + 1 >= bih.nodes.size())
            throw Error("invalid BIH: node " + std::to_string(i) + " has children out of range");
        stack.push_back({node.index(), depth + 1});
        stack.push_back({node.index() + 1, depth + 1});
    });
    if (covered != n)
        throw Error("invalid BIH: leaves reference " + std::to_string(covered) + " of " + std::to_string(n) +
                    " primitives");
}

namespace {

// NaN coordinates compare false and so pass: a primitive with NaN bounds is never hit anyway.
bool below(float v, float limit) { return v < limit; }

/// The bounds of node i's subtree, checking every plane on the way (depth is bounded by
/// validate_bih, so the recursion is too).
Aabb subtree_bounds(const BihData& bih, std::span<const Aabb> prim_bounds, uint32_t i) {
    const BihNode& node = bih.nodes[i];
    Aabb box;
    if (node.is_leaf()) {
        for (uint32_t e = node.index(); e < node.index() + node.count(); ++e) {
            const Aabb& b = prim_bounds[bih.prim_indices[e]];
            bool nan = false;
            for (int a = 0; a < 3; ++a) nan = nan || std::isnan(b.min[a]) || std::isnan(b.max[a]);
            if (!nan) box.grow(b);  // a NaN primitive is never hit: where it is listed does not matter
        }
        return box;
    }
    const int a = node.axis();
    if (std::isnan(node.left_max()) || std::isnan(node.right_min()))
        throw Error("invalid BIH: node " + std::to_string(i) + " has a NaN plane");
    const Aabb left = subtree_bounds(bih, prim_bounds, node.index());
    const Aabb right = subtree_bounds(bih, prim_bounds, node.index() + 1);
    if (!left.empty() && below(node.left_max(), left.max[a]))
        throw Error("invalid BIH: node " + std::to_string(i) + "'s left plane " + std::to_string(node.left_max()) +
                    " cuts its left subtree (which reaches " + std::to_string(left.max[a]) + ")");
    if (!right.empty() && below(right.min[a], node.right_min()))
        throw Error("invalid BIH: node " + std::to_string(i) + "'s right plane " + std::to_string(node.right_min()) +
                    " cuts its right subtree (which reaches " + std::to_string(right.min[a]) + ")");
    box.grow(left);
    box.grow(right);
    return box;
}

}  // namespace

void validate_bih_bounds(const BihData& bih, std::span<const Aabb> prim_bounds) {
    if (bih.nodes.empty()) return;
    const Aabb all = subtree_bounds(bih, prim_bounds, 0);
    for (int a = 0; a < 3; ++a)
        if (below(all.min[a], bih.bounds.min[a]) || below(bih.bounds.max[a], all.max[a]))
            throw Error("invalid BIH: the root box does not contain every primitive");
}

}  // namespace thicket
