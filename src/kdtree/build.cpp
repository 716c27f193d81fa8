// The shared part of kD-tree construction: choosing the primitives and the root voxel, the depth
// limit, and the figures and invariants of a built tree.
#include <algorithm>
#include <cmath>

#include "builder.h"
#include "thicket/core/depth_first.h"
#include "thicket/core/sah.h"

namespace thicket {

namespace {

bool finite(const Aabb& b) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(b.min[k]) || !std::isfinite(b.max[k])) return false;
    return !b.empty();
}

}  // namespace

uint32_t kd_max_depth(const KdBuildOptions& options, size_t primitives) {
    if (options.max_depth > 0) return std::min(options.max_depth, kKdMaxDepth);
    if (primitives < 2) return 8;
    const double depth = std::round(8.0 + 1.3 * std::log2(double(primitives)));
    return std::min(uint32_t(depth), kKdMaxDepth);
}

KdTreeData build_kdtree(const KdBuildInput& input, const KdBuildOptions& options) {
    KdTreeData tree;
    const size_t n = input.bounds.size();
    if (n > kKdMaxField)
        throw Error("kdtree: " + std::to_string(n) + " primitives exceed the limit of " + std::to_string(kKdMaxField));
    tree.primitives = uint32_t(n);
    std::vector<uint32_t> prims;
    prims.reserve(n);
    for (uint32_t i = 0; i < n; ++i) {
        if (!finite(input.bounds[i])) continue;  // NaN or infinite coordinates: never hit
        prims.push_back(i);
        tree.bounds.grow(input.bounds[i]);
    }
    if (prims.empty()) return tree;
    kd_build::TreeWriter out(tree);
    const uint32_t depth = kd_max_depth(options, prims.size());
    if (options.builder == KdBuilder::Median)
        kd_build::build_median(input, options.cost, depth, prims, tree.bounds, out);
    else
        kd_build::build_sah(input, options.cost, depth, prims, tree.bounds, out);
    return tree;
}

KdFigures kdtree_figures(const KdTreeData& tree, const KdCostModel& cost) {
    double builder_cost = 0.0;
    auto expand = [&](const TreeWalkItem& item, double rel, auto push) -> std::optional<size_t> {
        const KdNode& node = tree.nodes[item.node];
        if (node.is_leaf()) {
            builder_cost += rel * cost.intersection * node.count();
            return node.count();
        }
        builder_cost += rel * cost.traversal;
        Aabb below = item.box, above = item.box;
        below.max[node.axis()] = node.split();
        above.min[node.axis()] = node.split();
        push({node.above(), item.depth + 1, above});
        push({item.node + 1, item.depth + 1, below});
        return std::nullopt;
    };
    KdFigures f;
    static_cast<TreeFigures&>(f) = walk_tree(!tree.nodes.empty(), tree.bounds, expand);
    f.builder_cost = builder_cost;
    return f;
}

void validate_kdtree(const KdTreeData& tree, size_t primitive_count) {
    if (tree.primitives != primitive_count)
        throw Error("invalid kD-tree: built over " + std::to_string(tree.primitives) + " primitives, the scene has " +
                    std::to_string(primitive_count));
    if (tree.nodes.empty()) {
        if (!tree.prim_indices.empty()) throw Error("invalid kD-tree: primitive references without nodes");
        return;
    }
    if (!finite(tree.bounds)) throw Error("invalid kD-tree: root voxel is empty or not finite");
    for (uint32_t p : tree.prim_indices)
        if (p >= primitive_count) throw Error("invalid kD-tree: primitive index " + std::to_string(p) + " out of range");
    const size_t n = tree.nodes.size();
    std::vector<uint8_t> seen(n, 0);
    size_t reached = 0;
    depth_first(NodeAtDepth{0, 0}, [&](const NodeAtDepth& item, std::vector<NodeAtDepth>& stack) {
        const auto [i, depth] = item;
        if (seen[i]++) throw Error("invalid kD-tree: node " + std::to_string(i) + " is shared between subtrees");
        ++reached;
        const KdNode& node = tree.nodes[i];
        if (depth > kKdMaxDepth) throw Error("invalid kD-tree: deeper than " + std::to_string(kKdMaxDepth));
        if (node.is_leaf()) {
            if (uint64_t(node.first()) + node.count() > tree.prim_indices.size())
                throw Error("invalid kD-tree: leaf " + std::to_string(i) + " references entries out of range");
        } else {
            // Children come after their parent, the below one directly: no cycles, no sharing.
            if (!std::isfinite(node.split()) || node.above() <= i + 1 || node.above() >= n || i + 1 >= n)
                throw Error("invalid kD-tree: node " + std::to_string(i) + " has a bad split or children");
            stack.push_back({node.above(), depth + 1});
            stack.push_back({i + 1, depth + 1});
        }
    });
    if (reached != n) throw Error("invalid kD-tree: " + std::to_string(n - reached) + " nodes are unreachable");
}

}  // namespace thicket
