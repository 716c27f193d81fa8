// The top-down BVH build shared by every builder: node pool, recursion, leaf decisions, the
// depth bound, and the per-node child-order bytes the ordered traversals read.
#include "thicket/bvh/build.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "splitter.h"
#include "thicket/core/error.h"

namespace thicket {
namespace bvh_build {

Aabb centroid_bounds(const BuildContext& ctx, const NodeRange& node) {
    Aabb b;
    for (uint32_t i = node.first; i < node.first + node.count; ++i) b.grow(ctx.prims.centroids[ctx.indices[i]]);
    return b;
}

Split Splitter::median_split(const NodeRange& node) {
    const Aabb cb = centroid_bounds(ctx_, node);
    const int axis = cb.empty() ? 0 : max_axis(cb.extent());
    auto begin = ctx_.indices.begin() + node.first;
    const auto& c = ctx_.prims.centroids;
    // Ties broken by index so the result does not depend on the library's nth_element.
    std::nth_element(begin, begin + node.count / 2, begin + node.count, [&](uint32_t a, uint32_t b) {
        return c[a][axis] < c[b][axis] || (c[a][axis] == c[b][axis] && a < b);
    });
    return {node.count / 2, axis};
}

}  // namespace bvh_build

namespace {

using namespace bvh_build;

std::unique_ptr<Splitter> make_splitter(BuildContext& ctx) {
    switch (ctx.options.builder) {
    case BvhBuilder::Midpoint: return make_midpoint_splitter(ctx);
    case BvhBuilder::BinnedSah: return make_binned_sah_splitter(ctx);
    case BvhBuilder::SweepSah: return make_sweep_sah_splitter(ctx);
    }
    throw Error("unknown BVH builder");
}

Aabb range_bounds(const BuildPrimitives& prims, const std::vector<uint32_t>& indices, uint32_t first, uint32_t count) {
    Aabb b;
    for (uint32_t i = first; i < first + count; ++i) b.grow(prims.bounds[indices[i]]);
    return b;
}

/// Fills the centroid-axis bits of each interior node's order byte from its children's boxes.
void compute_child_order(BvhData& bvh) {
    for (uint32_t n = 0; n < bvh.nodes_used; ++n) {
        const BvhNode& node = bvh.nodes[n];
        if (n == 1 || node.is_leaf()) continue;
        const Vec3 cl = bvh.nodes[node.leftFirst].bounds().center();
        const Vec3 cr = bvh.nodes[node.leftFirst + 1].bounds().center();
        const int axis = max_axis(abs(cr - cl));
        bvh.child_order[n] = ChildOrder::pack(ChildOrder::split_axis(bvh.child_order[n]), axis, cl[axis] > cr[axis]);
    }
}

}  // namespace

BvhData build_bvh(const BuildPrimitives& prims, const BvhBuildOptions& options) {
    if (prims.bounds.size() != prims.centroids.size()) throw Error("build_bvh: bounds and centroids differ in size");
    if (prims.bounds.size() >= (1ull << 31)) throw Error("build_bvh: more than 2^31 primitives");
    const uint32_t n = uint32_t(prims.bounds.size());
    BvhData bvh;
    bvh.prim_indices.resize(n);
    std::iota(bvh.prim_indices.begin(), bvh.prim_indices.end(), 0u);
    if (n == 0) return bvh;

    // The lecture's pool: allocated once; 2N-1 nodes suffice, plus the unused slot 1 so that
    // every sibling pair shares a cache line.
    bvh.nodes.resize(2 * size_t(n));
    bvh.child_order.assign(2 * size_t(n), 0);
    bvh.nodes_used = 2;

    BuildContext ctx{prims, bvh.prim_indices, options};
    std::unique_ptr<Splitter> splitter = make_splitter(ctx);

    struct Task {
        uint32_t node, depth;
    };
    std::vector<Task> stack{{0, 0}};
    bvh.nodes[0].leftFirst = 0;
    bvh.nodes[0].count = n;
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        BvhNode& node = bvh.nodes[task.node];
        NodeRange range{node.leftFirst, node.count, range_bounds(prims, bvh.prim_indices, node.leftFirst, node.count)};
        node.aabbMin = range.bounds.min;
        node.aabbMax = range.bounds.max;
        if (range.count == 1) continue;

        Split split;
        if (task.depth >= kMaxSahDepth) {
            split = splitter->median_split(range);
        } else {
            split = splitter->split(range);
            if (split.left_count == 0 && range.count > uint32_t(options.max_leaf)) split = splitter->median_split(range);
        }
        if (split.left_count == 0 || split.left_count >= range.count) continue;  // stays a leaf

        const uint32_t left = bvh.nodes_used;
        bvh.nodes_used += 2;
        bvh.nodes[left].leftFirst = range.first;
        bvh.nodes[left].count = split.left_count;
        bvh.nodes[left + 1].leftFirst = range.first + split.left_count;
        bvh.nodes[left + 1].count = range.count - split.left_count;
        node.leftFirst = left;
        node.count = 0;
        bvh.child_order[task.node] = ChildOrder::pack(split.axis, 0, false);
        stack.push_back({left + 1, task.depth + 1});
        stack.push_back({left, task.depth + 1});
    }
    compute_child_order(bvh);
    return bvh;
}

BvhFigures bvh_figures(const BvhData& bvh) {
    if (bvh.nodes_used == 0) return {};
    auto expand = [&](const TreeWalkItem& item, double, auto push) -> std::optional<size_t> {
        const BvhNode& node = bvh.nodes[item.node];
        if (node.is_leaf()) return node.count;
        push({node.leftFirst, item.depth + 1, bvh.nodes[node.leftFirst].bounds()});
        push({node.leftFirst + 1, item.depth + 1, bvh.nodes[node.leftFirst + 1].bounds()});
        return std::nullopt;
    };
    return walk_tree(true, bvh.nodes[0].bounds(), expand);
}

void validate_bvh(const BvhData& bvh, size_t primitive_count) {
    const size_t n = primitive_count;
    if (bvh.prim_indices.size() != n)
        throw Error("invalid BVH: " + std::to_string(bvh.prim_indices.size()) + " primitive indices for " +
                    std::to_string(n) + " primitives");
    if (n == 0) {
        if (bvh.nodes_used != 0) throw Error("invalid BVH: nodes in a BVH over no primitives");
        return;
    }
    if (bvh.nodes_used < 2 || bvh.nodes_used > 2 * n || bvh.nodes.size() < bvh.nodes_used ||
        bvh.child_order.size() < bvh.nodes_used)
        throw Error("invalid BVH: " + std::to_string(bvh.nodes_used) + " nodes in use for " + std::to_string(n) +
                    " primitives");
    std::vector<uint8_t> referenced(n, 0);
    for (uint32_t idx : bvh.prim_indices) {
        if (idx >= n || referenced[idx]) throw Error("invalid BVH: primitive index array is not a permutation");
        referenced[idx] = 1;
    }
    struct Item {
        uint32_t node, depth;
    };
    std::vector<Item> stack{{0, 0}};
    size_t covered = 0;
    // Leaves must partition the index array: a leaf pointed at another's entries (a fuzzed file
    // did this) still covers n entries in total, but leaves primitives unreachable.
    std::vector<uint8_t> entry_seen(n, 0);
    while (!stack.empty()) {
        const auto [i, depth] = stack.back();
        stack.pop_back();
        const BvhNode& node = bvh.nodes[i];
        if (depth > kMaxDepth) throw Error("invalid BVH: deeper than " + std::to_string(kMaxDepth));
        if (node.is_leaf()) {
            if (uint64_t(node.leftFirst) + node.count > n)
                throw Error("invalid BVH: leaf " + std::to_string(i) + " references primitives out of range");
            for (uint32_t e = node.leftFirst; e < node.leftFirst + node.count; ++e)
                if (entry_seen[e]++) throw Error("invalid BVH: leaves overlap at primitive entry " + std::to_string(e));
            covered += node.count;
        } else {
            // Children always come after their parent: this rules out cycles.
            if (node.leftFirst <= i || node.leftFirst < 2 || uint64_t(node.leftFirst) + 1 >= bvh.nodes_used)
                throw Error("invalid BVH: node " + std::to_string(i) + " has children out of range");
            stack.push_back({node.leftFirst, depth + 1});
            stack.push_back({node.leftFirst + 1, depth + 1});
        }
    }
    if (covered != n) throw Error("invalid BVH: leaves reference " + std::to_string(covered) + " of " +
                                  std::to_string(n) + " primitives");
}

namespace {

/// True when `inner` sticks out of `outer` on some axis. NaN coordinates compare false and so
/// pass: a primitive with NaN bounds is never hit, wherever its box is.
bool sticks_out(const Aabb& inner, const Aabb& outer) {
    for (int a = 0; a < 3; ++a)
        if (inner.min[a] < outer.min[a] || inner.max[a] > outer.max[a]) return true;
    return false;
}

}  // namespace

void validate_bvh_bounds(const BvhData& bvh, std::span<const Aabb> prim_bounds) {
    if (bvh.nodes_used == 0) return;
    // Only the nodes traversal reaches (validate_bvh proved this walk stays in range).
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const uint32_t i = stack.back();
        stack.pop_back();
        const BvhNode& node = bvh.nodes[i];
        const Aabb box = node.bounds();
        for (int a = 0; a < 3; ++a)
            if (std::isnan(box.min[a]) || std::isnan(box.max[a]))
                throw Error("invalid BVH: node " + std::to_string(i) + " has a NaN box");
        if (node.is_leaf()) {
            for (uint32_t k = node.leftFirst; k < node.leftFirst + node.count; ++k)
                if (sticks_out(prim_bounds[bvh.prim_indices[k]], box))
                    throw Error("invalid BVH: leaf " + std::to_string(i) + "'s box does not contain primitive " +
                                std::to_string(bvh.prim_indices[k]));
            continue;
        }
        const uint8_t order = bvh.child_order[i];
        if (ChildOrder::split_axis(order) > 2 || ChildOrder::centroid_axis(order) > 2 || order >= 32)
            throw Error("invalid BVH: node " + std::to_string(i) + " has child-order byte " + std::to_string(order));
        for (uint32_t c = node.leftFirst; c <= node.leftFirst + 1; ++c) {
            if (sticks_out(bvh.nodes[c].bounds(), box))
                throw Error("invalid BVH: node " + std::to_string(i) + "'s box does not contain its child " +
                            std::to_string(c));
            stack.push_back(c);
        }
    }
}

}  // namespace thicket
