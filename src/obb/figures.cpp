// Figures and structural checks of a built OBB tree.
#include <algorithm>
#include <cmath>
#include <string>

#include "thicket/core/depth_first.h"
#include "thicket/core/error.h"
#include "thicket/core/sah.h"
#include "thicket/obb/build.h"

namespace thicket {

TreeFigures obb_figures(const ObbData& obb, float reference_area) {
    TreeFigures f;
    if (obb.nodes.empty()) return f;
    depth_first(NodeAtDepth{0, 0}, [&](const NodeAtDepth& item, std::vector<NodeAtDepth>& stack) {
        const ObbNode& node = obb.nodes[item.node];
        const double rel = reference_area > 0.0f ? double(obb_area(node)) / reference_area : 1.0;
        ++f.nodes;
        f.max_depth = std::max<size_t>(f.max_depth, item.depth);
        if (node.is_leaf()) {
            ++f.leaves;
            f.references += node.count;
            f.max_leaf_size = std::max<size_t>(f.max_leaf_size, node.count);
            f.sah_cost += rel * kSahIntersectionCost * double(node.count);
        } else {
            f.sah_cost += rel * kSahTraversalCost;
            stack.push_back({node.leftFirst + 1, item.depth + 1});
            stack.push_back({node.leftFirst, item.depth + 1});
        }
    });
    return f;
}

namespace {

[[noreturn]] void invalid(const std::string& what) { throw Error("invalid OBB tree: " + what); }

/// Throws unless node n's box is finite with non-negative extents and orthonormal axes.
void check_box(const ObbNode& b, size_t n) {
    const std::string at = "node " + std::to_string(n) + ": ";
    for (int k = 0; k < 3; ++k)
        if (!is_finite(b.axis[k]) || std::fabs(length(b.axis[k]) - 1.0f) > 1e-3f) invalid(at + "axis not of unit length");
    if (std::fabs(dot(b.axis[0], b.axis[1])) > 1e-3f || std::fabs(dot(b.axis[0], b.axis[2])) > 1e-3f ||
        std::fabs(dot(b.axis[1], b.axis[2])) > 1e-3f)
        invalid(at + "axes not orthogonal");
    if (!is_finite(b.center) || !is_finite(b.half) || b.half.x < 0 || b.half.y < 0 || b.half.z < 0)
        invalid(at + "box not finite or with a negative extent");
}

}  // namespace

void validate_obb(const ObbData& obb, size_t primitive_count) {
    const size_t n = primitive_count;
    if (obb.prim_indices.size() != n)
        invalid(std::to_string(obb.prim_indices.size()) + " primitive indices for " + std::to_string(n) + " primitives");
    if (n == 0) {
        if (!obb.nodes.empty()) invalid("nodes over no primitives");
        return;
    }
    if (obb.nodes.empty() || obb.nodes.size() > 2 * n) invalid(std::to_string(obb.nodes.size()) + " nodes for " +
                                                               std::to_string(n) + " primitives");
    std::vector<uint8_t> referenced(n, 0), reached(obb.nodes.size(), 0);
    std::vector<std::pair<uint32_t, uint32_t>> stack{{0, 0}};  // node, depth
    reached[0] = 1;
    while (!stack.empty()) {
        const auto [i, depth] = stack.back();
        stack.pop_back();
        if (depth > kObbMaxDepth) invalid("deeper than " + std::to_string(kObbMaxDepth));
        const ObbNode& node = obb.nodes[i];
        check_box(node, i);
        if (node.is_leaf()) {
            if (size_t(node.leftFirst) + node.count > n)
                invalid("node " + std::to_string(i) + " references indices past the end");
            for (uint32_t k = node.leftFirst; k < node.leftFirst + node.count; ++k) {
                const uint32_t p = obb.prim_indices[k];
                if (p >= n) invalid("primitive index " + std::to_string(p) + " out of range");
                if (referenced[p]++) invalid("primitive " + std::to_string(p) + " referenced twice");
            }
            continue;
        }
        if (node.leftFirst <= i || size_t(node.leftFirst) + 1 >= obb.nodes.size())
            invalid("node " + std::to_string(i) + " has children at " + std::to_string(node.leftFirst));
        for (uint32_t c : {node.leftFirst, node.leftFirst + 1}) {
            if (reached[c]++) invalid("node " + std::to_string(c) + " has two parents");
            stack.push_back({c, depth + 1});
        }
    }
    for (size_t p = 0; p < n; ++p)
        if (!referenced[p]) invalid("primitive " + std::to_string(p) + " in no leaf");
}

}  // namespace thicket
