// PLOC (Meister and Bittner 2018): bottom-up clustering along the Morton curve. Each round,
// every cluster finds its nearest neighbour within `radius` positions on either side (the
// distance: the area of the merged box), mutual pairs merge, and the survivors are compacted in
// order. Rounds run chunk by chunk as PLOC++ (Benthin et al. 2022) splits them: a chunk computes
// each pair of its window once and keeps the best for its own positions. Every result is a
// function of positions alone (fixed chunks, a total order on pairs), so the tree never depends
// on the threads. The leaves are cut afterwards with the SAH, then the tree is laid out depth
// first as every other builder lays out its own.
#include <algorithm>
#include <bit>
#include <cstring>
#include <numeric>

#include "morton.h"
#include "splitter.h"
#include "thicket/bvh/ploc.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

using bvh_build::sah_units;

/// Positions per chunk of a round's loops: fixed, so the chunks never depend on the threads.
constexpr size_t kRoundChunk = 2048;

/// A candidate pair (a < b positions) ordered by merged area, then by a hash of the pair, then
/// by the pair itself: a strict total order, so the globally best pair is always mutual (every
/// round merges) and equal areas (piles of identical boxes) pair up about evenly instead of all
/// choosing the same side, which would merge one pair per round.
struct PairKey {
    uint64_t major = ~0ull, minor = ~0ull;
    bool operator<(const PairKey& o) const { return major != o.major ? major < o.major : minor < o.minor; }
};

uint32_t mix_pair(uint32_t a, uint32_t b) {
    uint64_t x = (uint64_t(a) << 32 | b) * 0x9E3779B97F4A7C15ull;
    x ^= x >> 29;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 32;
    return uint32_t(x);
}

PairKey pair_key(const Aabb& ba, const Aabb& bb, uint32_t a, uint32_t b) {
    Aabb m = ba;
    m.grow(bb);
    const float area = m.half_area() + 0.0f;  // -0 to +0: the bits then order as the values
    // NaN (boxes of NaN or infinite corners) after every number.
    const uint32_t bits = area >= 0.0f ? std::bit_cast<uint32_t>(area) : ~0u;
    return {uint64_t(bits) << 32 | mix_pair(a, b), uint64_t(a) << 32 | b};
}

/// What happens to the cluster at a position in a round.
enum : uint8_t { kKeep = 0, kHead = 1, kGone = 2 };

class PlocBuild {
public:
    PlocBuild(const BuildPrimitives& prims, const BvhBuildOptions& o, PlocCounts& counts)
        : prims_(prims), o_(o), counts_(counts), threads_(resolve_threads(o.threads)) {}

    BvhData run() {
        BvhData bvh;
        const uint32_t n = uint32_t(prims_.bounds.size());
        bvh.prim_indices.resize(n);
        std::iota(bvh.prim_indices.begin(), bvh.prim_indices.end(), 0u);
        if (n == 0) return bvh;
        bvh_build::morton_sort(prims_.centroids, o_.threads, bvh.prim_indices);
        n_ = n;
        order_ = bvh.prim_indices;  // leaf p of the cluster tree is primitive order_[p]
        cluster();
        cut_leaves();
        lay_out(bvh);
        return bvh;
    }

private:
    /// The cluster tree: ids below n_ are leaves (sorted positions), id n_ + k the k-th merge.
    void cluster() {
        const uint32_t n = n_;
        box_.resize(2 * size_t(n) - 1);
        child_.resize(2 * size_t(n - 1));
        parallel_for(n, kRoundChunk, threads_, [&](size_t begin, size_t end) {
            for (size_t p = begin; p < end; ++p) box_[p] = prims_.bounds[order_[p]];
        });
        std::vector<uint32_t> cur(n), next;
        std::iota(cur.begin(), cur.end(), 0u);
        std::vector<uint32_t> nn;
        std::vector<uint8_t> action;
        uint32_t made = 0;  // merges so far
        const uint32_t r = std::max(1u, o_.ploc_radius);
        while (cur.size() > 1) {
            const uint32_t m = uint32_t(cur.size());
            ++counts_.iterations;
            counts_.cluster_visits += m;
            nn.assign(m, 0);
            const size_t chunks = (m + kRoundChunk - 1) / kRoundChunk;
            std::vector<uint64_t> evaluations(chunks, 0);
            parallel_for(m, kRoundChunk, threads_, [&](size_t begin, size_t end) {
                evaluations[begin / kRoundChunk] = nearest(cur, uint32_t(begin), uint32_t(end), r, nn);
            });
            for (uint64_t e : evaluations) counts_.distance_evaluations += e;
            action.assign(m, kKeep);
            parallel_for(m, kRoundChunk, threads_, [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i) {
                    const uint32_t j = nn[i];
                    if (nn[j] == i) action[i] = i < j ? kHead : kGone;
                }
            });
            // Per chunk: heads, and survivors (a head's partner may lie in another chunk).
            std::vector<uint32_t> heads(chunks, 0), keeps(chunks, 0);
            auto count_chunks = [&] {
                parallel_for(m, kRoundChunk, threads_, [&](size_t begin, size_t end) {
                    uint32_t h = 0, k = 0;
                    for (size_t i = begin; i < end; ++i) {
                        h += action[i] == kHead ? 1 : 0;
                        k += action[i] != kGone ? 1 : 0;
                    }
                    heads[begin / kRoundChunk] = h;
                    keeps[begin / kRoundChunk] = k;
                });
                return std::accumulate(heads.begin(), heads.end(), 0u);
            };
            uint32_t merges = count_chunks();
            // A chain of ever-wider gaps agrees on one pair a round: pair the rest in order so that
            // a round always removes a fixed share of the clusters (O(n) rounds would be O(n^2)).
            if (uint64_t(merges) * 32 < m) {
                ++counts_.forced_rounds;
                uint32_t open = m;  // a position waiting for a partner
                for (uint32_t i = 0; i < m; ++i) {
                    if (action[i] != kKeep) continue;
                    if (open == m) {
                        open = i;
                        continue;
                    }
                    action[open] = kHead;
                    action[i] = kGone;
                    nn[open] = i;
                    open = m;
                }
                merges = count_chunks();
            }
            // Survivors in order; the k-th head of the round becomes node n + made + k.
            std::vector<uint32_t> kept_at(chunks), head_at(chunks);
            uint32_t kept = 0, head = made;
            for (size_t c = 0; c < chunks; ++c) {
                kept_at[c] = kept;
                head_at[c] = head;
                kept += keeps[c];
                head += heads[c];
            }
            next.resize(kept);
            parallel_for(m, kRoundChunk, threads_, [&](size_t begin, size_t end) {
                uint32_t k = kept_at[begin / kRoundChunk], id = n + head_at[begin / kRoundChunk];
                for (size_t i = begin; i < end; ++i) {
                    if (action[i] == kGone) continue;
                    if (action[i] == kKeep) {
                        next[k++] = cur[i];
                        continue;
                    }
                    const uint32_t a = cur[i], b = cur[nn[i]];
                    child_[2 * size_t(id - n)] = a;
                    child_[2 * size_t(id - n) + 1] = b;
                    box_[id] = box_[a];
                    box_[id].grow(box_[b]);
                    next[k++] = id++;
                }
            });
            made += merges;
            cur.swap(next);
        }
        root_ = cur[0];
    }

    /// The nearest neighbour of each position in [lo, hi) among the m clusters `cur`, into nn;
    /// returns the areas computed. Pairs in the window [lo - r, hi + r) are computed once each.
    uint64_t nearest(const std::vector<uint32_t>& cur, uint32_t lo, uint32_t hi, uint32_t r,
                     std::vector<uint32_t>& nn) const {
        const uint32_t m = uint32_t(cur.size());
        std::vector<PairKey> best(hi - lo);
        uint64_t evaluations = 0;
        for (uint32_t a = lo > r ? lo - r : 0; a < hi; ++a) {
            const uint32_t last = std::min(m - 1, a + r);
            for (uint32_t b = std::max(a + 1, lo); b <= last; ++b) {
                const bool own_a = a >= lo, own_b = b < hi;
                if (!own_a && !own_b) continue;
                const PairKey key = pair_key(box_[cur[a]], box_[cur[b]], a, b);
                ++evaluations;
                if (own_a && key < best[a - lo]) {
                    best[a - lo] = key;
                    nn[a] = b;
                }
                if (own_b && key < best[b - lo]) {
                    best[b - lo] = key;
                    nn[b] = a;
                }
            }
        }
        return evaluations;
    }

    /// Marks the subtrees that become leaves: a subtree of at most max_leaf primitives whose
    /// cost as one leaf is no more than as a node with its best children (the SAH, leaves in
    /// blocks of sah_block). Children have smaller ids, so one pass in id order sees them first.
    void cut_leaves() {
        const uint32_t n = n_, block = std::max(1u, o_.sah_block);
        count_.assign(2 * size_t(n) - 1, 1);
        leaf_.assign(2 * size_t(n) - 1, 1);
        std::vector<float> cost(2 * size_t(n) - 1);
        for (uint32_t p = 0; p < n; ++p) cost[p] = kSahIntersectionCost * box_[p].half_area() * sah_units(1, block);
        for (uint32_t id = n; id + 1 < 2 * n; ++id) {
            const uint32_t a = child_[2 * size_t(id - n)], b = child_[2 * size_t(id - n) + 1];
            count_[id] = count_[a] + count_[b];
            const float area = box_[id].half_area();
            const float split = kSahTraversalCost * area + cost[a] + cost[b];
            const float leaf = kSahIntersectionCost * area * sah_units(count_[id], block);
            // A tie (zero areas) or NaN makes a leaf, as the top-down builders decide.
            leaf_[id] = count_[id] <= uint32_t(o_.max_leaf) && !(split < leaf);
            cost[id] = leaf_[id] ? leaf : split;
        }
    }

    /// Appends the primitives under cluster `id` to prim_indices at `at`, left to right.
    void gather(uint32_t id, std::vector<uint32_t>& out, uint32_t& at) {
        std::vector<uint32_t>& stack = gather_stack_;  // kept: one allocation, not one per leaf
        stack.assign(1, id);
        while (!stack.empty()) {
            const uint32_t c = stack.back();
            stack.pop_back();
            if (c < n_) {
                out[at++] = order_[c];
                continue;
            }
            stack.push_back(child_[2 * size_t(c - n_) + 1]);
            stack.push_back(child_[2 * size_t(c - n_)]);
        }
    }

    /// Writes the tree depth first: slot 0 the root, sibling pairs from 2, children after their
    /// parent. A subtree reaching kMaxSahDepth is laid out balanced by count instead (its
    /// primitives in cluster order, halved until leaves), so the depth stays below kMaxDepth.
    void lay_out(BvhData& bvh) {
        const uint32_t n = n_;
        bvh.nodes.resize(2 * size_t(n));
        bvh.child_order.assign(2 * size_t(n), 0);
        bvh.nodes_used = 2;
        uint32_t at = 0;  // next free entry of prim_indices
        struct Item {
            uint32_t id, slot, depth;
        };
        std::vector<Item> stack{{root_, 0, 0}};
        while (!stack.empty()) {
            const Item it = stack.back();
            stack.pop_back();
            BvhNode& node = bvh.nodes[it.slot];
            node.aabbMin = box_[it.id].min;
            node.aabbMax = box_[it.id].max;
            if (it.id < n || leaf_[it.id]) {
                node.leftFirst = at;
                node.count = count_[it.id];
                gather(it.id, bvh.prim_indices, at);
                continue;
            }
            if (it.depth >= kMaxSahDepth) {
                const uint32_t first = at;
                gather(it.id, bvh.prim_indices, at);
                ++counts_.balanced_subtrees;
                balanced(bvh, it.slot, first, at - first);
                continue;
            }
            uint32_t a = child_[2 * size_t(it.id - n)], b = child_[2 * size_t(it.id - n) + 1];
            // The left child is the lower one on the axis of widest centroid separation.
            const Vec3 ca = box_[a].center(), cb = box_[b].center();
            const int axis = max_axis(abs(cb - ca));
            if (cb[axis] < ca[axis]) std::swap(a, b);
            const uint32_t left = bvh.nodes_used;
            bvh.nodes_used += 2;
            node.leftFirst = left;
            node.count = 0;
            bvh.child_order[it.slot] = ChildOrder::pack(axis, 0, false);
            stack.push_back({b, left + 1, it.depth + 1});
            stack.push_back({a, left, it.depth + 1});
        }
    }

    /// Lays out prim_indices[first, first+count) under `slot` by halving the count (the
    /// primitives stay in cluster order: neighbours stay together).
    void balanced(BvhData& bvh, uint32_t slot, uint32_t first, uint32_t count) {
        struct Range {
            uint32_t slot, first, count;
        };
        std::vector<Range> stack{{slot, first, count}};
        while (!stack.empty()) {
            const Range r = stack.back();
            stack.pop_back();
            BvhNode& node = bvh.nodes[r.slot];
            Aabb box;
            for (uint32_t k = r.first; k < r.first + r.count; ++k) box.grow(prims_.bounds[bvh.prim_indices[k]]);
            node.aabbMin = box.min;
            node.aabbMax = box.max;
            if (r.count <= uint32_t(o_.max_leaf) || r.count == 1) {
                node.leftFirst = r.first;
                node.count = r.count;
                continue;
            }
            const uint32_t left = bvh.nodes_used, half = r.count / 2;
            bvh.nodes_used += 2;
            node.leftFirst = left;
            node.count = 0;
            bvh.child_order[r.slot] = ChildOrder::pack(max_axis(box.extent()), 0, false);
            stack.push_back({left + 1, r.first + half, r.count - half});
            stack.push_back({left, r.first, half});
        }
    }

    const BuildPrimitives& prims_;
    const BvhBuildOptions& o_;
    PlocCounts& counts_;
    unsigned threads_;
    uint32_t n_ = 0, root_ = 0;
    std::vector<uint32_t> order_;
    std::vector<Aabb> box_;
    std::vector<uint32_t> child_;  ///< the two children of merge k at 2k and 2k + 1
    std::vector<uint32_t> count_;  ///< primitives under each cluster
    std::vector<uint8_t> leaf_;    ///< whether each cluster becomes one leaf (cut_leaves)
    std::vector<uint32_t> gather_stack_;
};

}  // namespace

BvhData build_ploc(const BuildPrimitives& prims, const BvhBuildOptions& options, PlocCounts* counts) {
    if (prims.bounds.size() != prims.centroids.size()) throw Error("build_ploc: bounds and centroids differ in size");
    if (prims.bounds.size() >= (1ull << 31)) throw Error("build_ploc: more than 2^31 primitives");
    PlocCounts local;
    return PlocBuild(prims, options, counts ? *counts : local).run();
}

}  // namespace thicket
