// The top-down BVH build shared by every builder: node pool, explicit stacks, leaf decisions,
// the depth bound, the per-node child-order bytes the ordered traversals read, and the split of
// the work between threads (top nodes together, then one subtree per task) in a way that keeps
// the result byte-identical on any number of threads.
#include "thicket/core/depth_first.h"
#include "thicket/bvh/build.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "coverage.h"
#include "splitter.h"
#include "thicket/bvh/ploc.h"
#include "thicket/bvh/reinsertion.h"
#include "thicket/core/error.h"

namespace thicket {
namespace bvh_build {

/// Bounds over positions [first, first+count) of f(prim); a top node's chunk by chunk on
/// `threads` threads, merged in chunk order.
template <class Box>
Aabb range_box(const BuildContext& ctx, uint32_t first, uint32_t count, unsigned threads, Box&& box) {
    Aabb b;
    if (count < kParallelNodeSize) {
        for (uint32_t i = first; i < first + count; ++i) b.grow(box(ctx.indices[i]));
        return b;
    }
    std::vector<Aabb> partial(chunk_count(count));
    for_each_chunk(first, count, threads, [&](size_t c, uint32_t lo, uint32_t hi) {
        for (uint32_t i = lo; i < hi; ++i) partial[c].grow(box(ctx.indices[i]));
    });
    for (const Aabb& p : partial) b.grow(p);
    return b;
}

Aabb centroid_bounds(const BuildContext& ctx, const NodeRange& node, unsigned threads) {
    if (node.centroids_known) return node.centroids;
    return range_box(ctx, node.first, node.count, threads, [&](uint32_t prim) { return ctx.prims.centroids[prim]; });
}

Split Splitter::median_split(const NodeRange& node) {
    const Aabb cb = centroid_bounds(ctx_, node);
    const int axis = cb.empty() ? 0 : max_axis(cb.extent());
    auto begin = ctx_.indices.begin() + node.first;
    const auto& c = ctx_.prims.centroids;
    std::nth_element(begin, begin + node.count / 2, begin + node.count,
                     [&](uint32_t a, uint32_t b) { return centroid_before(c[a][axis], a, c[b][axis], b); });
    return plain_split(node.count / 2, axis);
}

}  // namespace bvh_build

namespace {

using namespace bvh_build;

std::unique_ptr<Splitter> make_splitter(BuildContext& ctx) {
    switch (ctx.options.builder) {
    case BvhBuilder::Midpoint: return make_midpoint_splitter(ctx);
    case BvhBuilder::BinnedSah: return make_binned_sah_splitter(ctx);
    case BvhBuilder::SweepSah: return make_sweep_sah_splitter(ctx);
    case BvhBuilder::Lbvh: return make_lbvh_splitter(ctx);
    case BvhBuilder::Sbvh:  // build_bvh calls build_sbvh instead
    case BvhBuilder::Ploc: break;  // bottom-up: build_bvh calls build_ploc instead
    }
    throw Error("unknown BVH builder");
}

/// Fills the centroid-axis bits of each interior node's order byte, and which child is higher on
/// its split axis, from its children's boxes' centres (refit.cpp recomputes them the same way).
void compute_child_order(BvhData& bvh) {
    for (uint32_t n = 0; n < bvh.nodes_used; ++n) {
        const BvhNode& node = bvh.nodes[n];
        if (n == 1 || node.is_leaf()) continue;
        bvh.child_order[n] = ChildOrder::from_children(ChildOrder::split_axis(bvh.child_order[n]),
                                                       bvh.nodes[node.leftFirst].bounds(),
                                                       bvh.nodes[node.leftFirst + 1].bounds());
    }
}

struct Task {
    uint32_t node, depth;
    bool bounded = false;  ///< the node's box is already stored (its parent's split knew it)
    bool centroids_known = false;  ///< centroids holds its centroids' bounds
    Aabb centroids;
};

/// The tasks of the children of a node split by `split` at pair `left`.
std::pair<Task, Task> child_tasks(const Split& split, uint32_t left, uint32_t depth) {
    Task l{left, depth + 1, split.bounded, split.centroids_known, split.left_centroids};
    Task r{left + 1, depth + 1, split.bounded, split.centroids_known, split.right_centroids};
    return {l, r};
}

/// Whether a node of `count` primitives is split on block boundaries (block_split): with
/// leaves weighed in blocks, by the SAH builders. Their splitters never see such a node nor any
/// below it (sweep-sah's axis orders of its range go stale, unread).
bool packs_blocks(const BvhBuildOptions& o, uint32_t count) {
    return o.sah_block > 1 && count <= kBlockPackMax &&
           (o.builder == BvhBuilder::BinnedSah || o.builder == BvhBuilder::SweepSah);
}

/// Bounds `node` (its range in leftFirst/count) unless task.bounded, and chooses its split, on up to `threads`
/// threads if it is a top node. left_count 0: it stays a leaf.
Split bound_and_split(BuildContext& ctx, Splitter& splitter, BvhNode& node, const Task& task, unsigned threads) {
    NodeRange range{node.leftFirst, node.count, node.bounds(), task.centroids_known, task.centroids};
    if (!task.bounded) {
        range.bounds =
            range_box(ctx, range.first, range.count, threads, [&](uint32_t prim) { return ctx.prims.bounds[prim]; });
        node.aabbMin = range.bounds.min;
        node.aabbMax = range.bounds.max;
    }
    const uint32_t depth = task.depth;
    if (range.count == 1) return {};
    Split split;
    if (packs_blocks(ctx.options, range.count)) {
        split = block_split(ctx, range, depth);
    } else if (depth >= kMaxSahDepth) {
        split = splitter.median_split(range);
    } else {
        split = splitter.split(range, threads);
        if (split.left_count == 0 && range.count > uint32_t(ctx.options.max_leaf)) split = splitter.median_split(range);
    }
    if (split.left_count >= range.count) return {};
    return split;
}

/// Makes node `index` of `nodes` an interior node whose children are a new pair at the
/// end of `nodes`; returns the left child's index.
uint32_t add_children(AlignedVector<BvhNode, 64>& nodes, std::vector<uint8_t>& order, uint32_t& used, uint32_t index,
                      const Split& split) {
    const uint32_t left = used;
    used += 2;
    if (nodes.size() < used) {  // a subtree's arrays grow as used (their capacity is reserved)
        nodes.resize(used);
        order.resize(used);
    }
    BvhNode& node = nodes[index];
    nodes[left].leftFirst = node.leftFirst;
    nodes[left].count = split.left_count;
    nodes[left + 1].leftFirst = node.leftFirst + split.left_count;
    nodes[left + 1].count = node.count - split.left_count;
    if (split.bounded) {
        nodes[left].aabbMin = split.left_bounds.min;
        nodes[left].aabbMax = split.left_bounds.max;
        nodes[left + 1].aabbMin = split.right_bounds.min;
        nodes[left + 1].aabbMax = split.right_bounds.max;
    }
    node.leftFirst = left;
    node.count = 0;
    order[index] = ChildOrder::pack(split.axis, 0, false);
    return left;
}

/// A subtree built on one thread into its own arrays, laid out as a whole BVH is: slot 0 its
/// root, slot 1 unused, pairs from 2, so its pairs stay 64-byte aligned once moved to an even base.
struct Subtree {
    AlignedVector<BvhNode, 64> nodes;
    std::vector<uint8_t> order;
    uint32_t used = 2;
    uint32_t base = 0;  ///< where slot 2 lands in the final pool
};

/// Builds the subtree rooted at `root` (a copy of its node: range in leftFirst/count) depth
/// first with an explicit stack.
void build_subtree(BuildContext& ctx, Splitter& splitter, const BvhNode& root, const Task& root_task, Subtree& out) {
    // Reserved, not filled: only the pages the subtree uses are ever touched.
    reserve_huge(out.nodes, 2 * size_t(root.count));
    reserve_huge(out.order, 2 * size_t(root.count));
    out.nodes.resize(2);
    out.order.resize(2);
    out.nodes[0] = root;
    std::vector<Task> stack{root_task};
    stack.back().node = 0;
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        const Split split = bound_and_split(ctx, splitter, out.nodes[task.node], task, 1);
        if (split.left_count == 0) continue;
        const auto [l, r] = child_tasks(split, add_children(out.nodes, out.order, out.used, task.node, split), task.depth);
        stack.push_back(r);
        stack.push_back(l);
    }
}

}  // namespace

BvhData build_bvh(const BuildPrimitives& prims, const BvhBuildOptions& options) {
    if (prims.bounds.size() != prims.centroids.size()) throw Error("build_bvh: bounds and centroids differ in size");
    if (prims.bounds.size() >= (1ull << 31)) throw Error("build_bvh: more than 2^31 primitives");
    const uint32_t n = uint32_t(prims.bounds.size());
    if (options.builder == BvhBuilder::Sbvh || options.builder == BvhBuilder::Ploc) {
        BvhData bvh = options.builder == BvhBuilder::Sbvh ? build_sbvh(prims, options) : build_ploc(prims, options);
        compute_child_order(bvh);
        if (options.optimize == BvhOptimize::Reinsertion) optimize_reinsertion(bvh, options.optimize_passes);
        return bvh;
    }
    BvhData bvh;
    reserve_huge(bvh.prim_indices, n);
    bvh.prim_indices.resize(n);
    std::iota(bvh.prim_indices.begin(), bvh.prim_indices.end(), 0u);
    if (n == 0) return bvh;

    // The lecture's pool: allocated once; 2N-1 nodes suffice, plus the unused slot 1 so that
    // every sibling pair shares a cache line. Reserved, not filled: leaves of about 4 primitives
    // use a quarter of it, and zeroing all 2N (56 MB on the dragon) cost more page faults than
    // the nodes written; the pool grows as used (add_children) within the one allocation.
    reserve_huge(bvh.nodes, 2 * size_t(n));
    reserve_huge(bvh.child_order, 2 * size_t(n));
    bvh.nodes.resize(2);
    bvh.child_order.assign(2, 0);
    bvh.nodes_used = 2;
    bvh.nodes[0].leftFirst = 0;
    bvh.nodes[0].count = n;

    const unsigned threads = resolve_threads(options.threads);
    BuildContext ctx{prims, bvh.prim_indices, options};
    std::unique_ptr<Splitter> splitter = make_splitter(ctx);

    // Top nodes, depth first, each with all threads; smaller nodes are set aside as subtree roots
    // in the order met, which depends on the sizes alone.
    std::vector<Task> stack{Task{0, 0, false, false, {}}}, roots;
    while (!stack.empty()) {
        const Task task = stack.back();
        stack.pop_back();
        if (bvh.nodes[task.node].count < kParallelNodeSize) {
            roots.push_back(task);
            continue;
        }
        const Split split = bound_and_split(ctx, *splitter, bvh.nodes[task.node], task, threads);
        if (split.left_count == 0) continue;
        const auto [l, r] =
            child_tasks(split, add_children(bvh.nodes, bvh.child_order, bvh.nodes_used, task.node, split), task.depth);
        stack.push_back(r);
        stack.push_back(l);
    }

    // Subtrees as tasks, biggest first for balance (the order they run in changes nothing).
    std::vector<Subtree> subtrees(roots.size());
    std::vector<size_t> by_size(roots.size());
    std::iota(by_size.begin(), by_size.end(), size_t(0));
    std::stable_sort(by_size.begin(), by_size.end(),
                     [&](size_t a, size_t b) { return bvh.nodes[roots[a].node].count > bvh.nodes[roots[b].node].count; });
    parallel_for(roots.size(), 1, threads, [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {
            const Task& root = roots[by_size[k]];
            build_subtree(ctx, *splitter, bvh.nodes[root.node], root, subtrees[by_size[k]]);
        }
    });

    // Each subtree's pairs go after the top nodes, in the order their roots were met.
    for (Subtree& s : subtrees) {
        s.base = bvh.nodes_used;
        bvh.nodes_used += s.used - 2;
    }
    bvh.nodes.resize(bvh.nodes_used);  // within the reservation: every new slot is written below
    bvh.child_order.resize(bvh.nodes_used);
    parallel_for(roots.size(), 1, threads, [&](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k) {
            const Subtree& s = subtrees[k];
            auto place = [&](BvhNode node) {  // local pair index -> pool index
                if (!node.is_leaf()) node.leftFirst = node.leftFirst - 2 + s.base;
                return node;
            };
            bvh.nodes[roots[k].node] = place(s.nodes[0]);
            bvh.child_order[roots[k].node] = s.order[0];
            for (uint32_t i = 2; i < s.used; ++i) {
                bvh.nodes[s.base + i - 2] = place(s.nodes[i]);
                bvh.child_order[s.base + i - 2] = s.order[i];
            }
        }
    });
    compute_child_order(bvh);
    if (options.optimize == BvhOptimize::Reinsertion) optimize_reinsertion(bvh, options.optimize_passes);
    return bvh;
}

std::string reference_figure(size_t references, size_t primitives) {
    char per[32];
    std::snprintf(per, sizeof per, "%.2f", primitives ? double(references) / double(primitives) : 0.0);
    return std::to_string(references) + " (" + per + " per primitive)";
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
    const size_t entries = bvh.prim_indices.size();
    // More entries than primitives: a spatial-split tree (sbvh) lists some in several leaves.
    if (entries < n || entries > size_t(kMaxReferencesPerPrimitive) * n)
        throw Error("invalid BVH: " + std::to_string(entries) + " primitive indices for " + std::to_string(n) +
                    " primitives");
    if (n == 0) {
        if (bvh.nodes_used != 0) throw Error("invalid BVH: nodes in a BVH over no primitives");
        return;
    }
    if (bvh.nodes_used < 2 || bvh.nodes_used > 2 * entries || bvh.nodes.size() < bvh.nodes_used ||
        bvh.child_order.size() < bvh.nodes_used)
        throw Error("invalid BVH: " + std::to_string(bvh.nodes_used) + " nodes in use for " + std::to_string(entries) +
                    " primitive indices");
    std::vector<uint8_t> referenced(n, 0);
    for (uint32_t idx : bvh.prim_indices) {
        if (idx >= n) throw Error("invalid BVH: primitive index " + std::to_string(idx) + " out of range");
        referenced[idx] = 1;
    }
    for (size_t p = 0; p < n; ++p)
        if (!referenced[p]) throw Error("invalid BVH: primitive " + std::to_string(p) + " is in no leaf");
    size_t covered = 0;
    // Leaves must partition the index array: a leaf pointed at another's entries (a fuzzed file
    // did this) still covers every entry in total, but leaves primitives unreachable.
    std::vector<uint8_t> entry_seen(entries, 0);
    depth_first(NodeAtDepth{0, 0}, [&](const NodeAtDepth& item, std::vector<NodeAtDepth>& stack) {
        const auto [i, depth] = item;
        const BvhNode& node = bvh.nodes[i];
        if (depth > kMaxDepth) throw Error("invalid BVH: deeper than " + std::to_string(kMaxDepth));
        if (node.is_leaf()) {
            if (uint64_t(node.leftFirst) + node.count > entries)
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
    });
    if (covered != entries) throw Error("invalid BVH: leaves reference " + std::to_string(covered) + " of " +
                                        std::to_string(entries) + " primitive entries");
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

void validate_bvh_bounds(const BvhData& bvh, std::span<const Aabb> prim_bounds, const ClipFunction& clip) {
    if (bvh.nodes_used == 0) return;
    // Every leaf that lists each primitive (compressed rows: leaves_of[first_of[p] .. first_of[p+1])).
    const size_t n = prim_bounds.size();
    std::vector<uint32_t> first_of(n + 1, 0), leaves_of(bvh.prim_indices.size());
    // Only the nodes traversal reaches (validate_bvh proved this walk stays in range).
    std::vector<uint32_t> stack{0}, leaves;
    while (!stack.empty()) {
        const uint32_t i = stack.back();
        stack.pop_back();
        const BvhNode& node = bvh.nodes[i];
        const Aabb box = node.bounds();
        for (int a = 0; a < 3; ++a)
            if (std::isnan(box.min[a]) || std::isnan(box.max[a]))
                throw Error("invalid BVH: node " + std::to_string(i) + " has a NaN box");
        if (node.is_leaf()) {
            leaves.push_back(i);
            for (uint32_t k = node.leftFirst; k < node.leftFirst + node.count; ++k) ++first_of[bvh.prim_indices[k] + 1];
            continue;
        }
        const uint8_t order = bvh.child_order[i];
        if (ChildOrder::split_axis(order) > 2 || ChildOrder::centroid_axis(order) > 2 || order >= ChildOrder::kBits)
            throw Error("invalid BVH: node " + std::to_string(i) + " has child-order byte " + std::to_string(order));
        for (uint32_t c = node.leftFirst; c <= node.leftFirst + 1; ++c) {
            if (sticks_out(bvh.nodes[c].bounds(), box))
                throw Error("invalid BVH: node " + std::to_string(i) + "'s box does not contain its child " +
                            std::to_string(c));
            stack.push_back(c);
        }
    }
    for (size_t p = 0; p < n; ++p) first_of[p + 1] += first_of[p];
    std::vector<uint32_t> fill(first_of.begin(), first_of.end() - 1);
    for (uint32_t leaf : leaves) {
        const BvhNode& node = bvh.nodes[leaf];
        for (uint32_t k = node.leftFirst; k < node.leftFirst + node.count; ++k)
            leaves_of[fill[bvh.prim_indices[k]]++] = leaf;
    }
    CoverageProof proof(prim_bounds, clip);
    std::vector<Aabb> boxes;
    for (uint32_t p = 0; p < n; ++p) {
        const uint32_t first = first_of[p], count = first_of[p + 1] - first;
        if (count == 1) {  // the common case, and every primitive of an object-partition tree
            const uint32_t leaf = leaves_of[first];
            if (sticks_out(prim_bounds[p], bvh.nodes[leaf].bounds()))
                throw Error("invalid BVH: leaf " + std::to_string(leaf) + "'s box does not contain primitive " +
                            std::to_string(p));
            continue;
        }
        boxes.clear();
        for (uint32_t k = first; k < first + count; ++k) boxes.push_back(bvh.nodes[leaves_of[k]].bounds());
        proof.check(p, boxes);
    }
}

}  // namespace thicket
