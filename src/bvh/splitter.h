#pragma once
// Internal to the BVH builders: the one thing a builder decides is how to split a node.
#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include "thicket/bvh/build.h"
#include "thicket/core/ray.h"
#include "thicket/core/sah.h"
#include "thicket/util/parallel.h"

namespace thicket::bvh_build {

struct NodeRange {
    uint32_t first = 0, count = 0;
    Aabb bounds;                   ///< of the primitives' bounds in the range
    bool centroids_known = false;  ///< centroids holds their centroids' bounds (the parent's partition found them)
    Aabb centroids;
};

/// left_count == 0 means "make a leaf"; otherwise indices[first, first+left_count) is the left child.
struct Split {
    uint32_t left_count = 0;
    int axis = 0;  ///< the left child lies on the lower side of this axis
    /// The children's boxes when the splitter has them anyway (bins, a sweep): the build then
    /// skips one pass over each child's primitives. Exactly what that pass would compute.
    bool bounded = false;
    Aabb left_bounds, right_bounds;
    /// The children's centroid bounds when the partition found them (partition_node does).
    bool centroids_known = false;
    Aabb left_centroids, right_centroids;
};

/// A split without any boxes: left_count and axis only.
inline Split plain_split(uint32_t left_count, int axis) {
    Split s;
    s.left_count = left_count;
    s.axis = axis;
    return s;
}

/// What partition_node did: the left side's size and both sides' centroid bounds.
struct Partition {
    uint32_t left = 0;
    Aabb left_centroids, right_centroids;
};

struct BuildContext {
    BuildPrimitives prims;
    std::vector<uint32_t>& indices;
    BvhBuildOptions options;
};

/// The order of primitives along an axis: by centroid coordinate, NaN after every number, ties by
/// primitive id. A total order, so sorts never see an inconsistent comparison (NaN compares false
/// both ways: as a sort key it made "equal" intransitive) and the result never depends on the
/// library's sort.
inline bool centroid_before(float ka, uint32_t a, float kb, uint32_t b) {
    const bool na = ka != ka, nb = kb != kb;  // NaN
    if (na != nb) return nb;
    if (!na && ka != kb) return ka < kb;
    return a < b;
}

/// What a leaf of `count` primitives costs to test, in primitive tests: its blocks of `block`
/// (BvhBuildOptions::sah_block; 1: the count itself).
inline float sah_units(uint32_t count, uint32_t block) {
    return block <= 1 ? float(count) : float((uint64_t(count) + block - 1) / block);
}

/// SAH cost of a split relative to its parent, leaves weighed in blocks of `block`; a
/// degenerate (zero-area) parent makes every split cost more than the leaf, so only max_leaf
/// forces one.
inline float sah_split_cost(float left_half_area, uint32_t left_count, float right_half_area, uint32_t right_count,
                            float parent_half_area, uint32_t block) {
    const float left = sah_units(left_count, block), right = sah_units(right_count, block);
    if (!(parent_half_area > 0.0f)) return kSahTraversalCost + kSahIntersectionCost * (left + right);
    return kSahTraversalCost +
           kSahIntersectionCost * (left_half_area * left + right_half_area * right) / parent_half_area;
}

inline float sah_leaf_cost(uint32_t count, uint32_t block) { return kSahIntersectionCost * sah_units(count, block); }

/// The SAH sweep every builder runs along one axis: `slots` consecutive slots (bins, or
/// primitives in axis order), plane p lying between slots p and p + 1. box_of(s) is slot s's box,
/// enters(s) the references counted on the left of every plane after s, exits(s) those counted
/// on the right of every plane before s (the same count for object splits; a straddling
/// reference of a spatial split enters in one bin and exits in another). right_area and
/// right_count are scratch for `slots` entries. Calls candidate(p, cost, left_count, right_count)
/// for every plane with references on both sides, from left to right; costs weigh leaves in
/// blocks of `block` (sah_units).
template <class BoxOf, class Enters, class Exits, class Candidate>
inline void sah_sweep(uint32_t slots, BoxOf&& box_of, Enters&& enters, Exits&& exits, float parent_half_area,
                      uint32_t block, float* right_area, uint32_t* right_count, Candidate&& candidate) {
    if (slots < 2) return;
    Aabb acc;
    uint32_t count = 0;
    for (uint32_t p = slots - 1; p > 0; --p) {  // right of plane p - 1: slots p..
        acc.grow(box_of(p));
        count += exits(p);
        right_area[p - 1] = acc.half_area();
        right_count[p - 1] = count;
    }
    acc = Aabb{};
    count = 0;
    for (uint32_t p = 0; p + 1 < slots; ++p) {
        acc.grow(box_of(p));
        count += enters(p);
        if (count == 0 || right_count[p] == 0) continue;
        candidate(p, sah_split_cost(acc.half_area(), count, right_area[p], right_count[p], parent_half_area, block),
                  count, right_count[p]);
    }
}

/// A top node's loops run over at most kMaxChunks chunks of at least kMinChunk primitives: a
/// function of the node's size alone, so the chunks, and hence every result merged in chunk
/// order, are the same whatever the number of threads.
inline constexpr uint32_t kMinChunk = 4096;
inline constexpr uint32_t kMaxChunks = 64;

/// Chunk length for a range of `count` primitives.
inline uint32_t chunk_size(uint32_t count) { return std::max(kMinChunk, (count + kMaxChunks - 1) / kMaxChunks); }
/// Number of chunks of a range of `count` primitives.
inline size_t chunk_count(uint32_t count) { return (size_t(count) + chunk_size(count) - 1) / chunk_size(count); }

/// Calls f(chunk, begin, end) for the chunks of positions [first, first+count) on up to
/// `threads` threads.
template <class F>
void for_each_chunk(uint32_t first, uint32_t count, unsigned threads, F&& f) {
    const uint32_t size = chunk_size(count);
    parallel_for(chunk_count(count), 1, threads, [&](size_t begin, size_t end) {
        for (size_t c = begin; c < end; ++c) {
            const uint32_t lo = first + uint32_t(c) * size;
            f(c, lo, lo + std::min(size, first + count - lo));
        }
    });
}

/// Bounds of the centroids of indices[first, first+count) (node.centroids when known); a top
/// node's on `threads` threads.
Aabb centroid_bounds(const BuildContext& ctx, const NodeRange& node, unsigned threads = 1);

/// Reorders the node's range so the primitives with goes_left(prim) come first; returns how
/// many they are and both sides' centroid bounds (gathered on the way: the children need not
/// scan their centroids again). A top node (kParallelNodeSize or more) is partitioned stably,
/// chunk by chunk on `threads` threads through a scratch copy; a smaller one in place,
/// quicksort-style.
template <class GoesLeft>
Partition partition_node(BuildContext& ctx, const NodeRange& node, unsigned threads, GoesLeft&& goes_left) {
    auto& idx = ctx.indices;
    const auto& cen = ctx.prims.centroids;
    Partition out;
    if (node.count < kParallelNodeSize) {
        uint32_t i = node.first, j = node.first + node.count;  // [first, i) left, [j, end) right
        while (i < j) {
            if (goes_left(idx[i])) {
                out.left_centroids.grow(cen[idx[i]]);
                ++i;
            } else {
                std::swap(idx[i], idx[--j]);
                out.right_centroids.grow(cen[idx[j]]);
            }
        }
        out.left = i - node.first;
        return out;
    }
    const size_t chunks = chunk_count(node.count);
    std::vector<uint32_t> lefts(chunks);
    std::vector<uint8_t> side(node.count);
    std::vector<Aabb> left_cb(chunks), right_cb(chunks);
    for_each_chunk(node.first, node.count, threads, [&](size_t c, uint32_t lo, uint32_t hi) {
        uint32_t n = 0;
        for (uint32_t k = lo; k < hi; ++k) {
            const bool left = goes_left(idx[k]);
            side[k - node.first] = left ? 1 : 0;
            n += left ? 1 : 0;
            (left ? left_cb[c] : right_cb[c]).grow(cen[idx[k]]);
        }
        lefts[c] = n;
    });
    for (size_t c = 0; c < chunks; ++c) {  // in chunk order: the same boxes on any thread count
        out.left_centroids.grow(left_cb[c]);
        out.right_centroids.grow(right_cb[c]);
    }
    std::vector<uint32_t> left_at(chunks), right_at(chunks);  // where each chunk's sides go
    uint32_t left_total = 0;
    for (size_t c = 0; c < chunks; ++c) left_total += lefts[c];
    uint32_t l = 0, r = left_total;
    for (size_t c = 0; c < chunks; ++c) {
        const uint32_t size = std::min(chunk_size(node.count), node.count - uint32_t(c) * chunk_size(node.count));
        left_at[c] = l;
        right_at[c] = r;
        l += lefts[c];
        r += size - lefts[c];
    }
    std::vector<uint32_t> scratch(node.count);
    for_each_chunk(node.first, node.count, threads, [&](size_t c, uint32_t lo, uint32_t hi) {
        uint32_t a = left_at[c], b = right_at[c];
        for (uint32_t k = lo; k < hi; ++k) scratch[side[k - node.first] ? a++ : b++] = idx[k];
    });
    parallel_for(node.count, chunk_size(node.count), threads, [&](size_t begin, size_t end) {
        std::copy(scratch.begin() + ptrdiff_t(begin), scratch.begin() + ptrdiff_t(end),
                  idx.begin() + ptrdiff_t(node.first + begin));
    });
    out.left = left_total;
    return out;
}

/// Chooses how to split a node. One splitter serves a whole build and may be called from several
/// threads at once, on disjoint ranges: whatever state it keeps is indexed by range position or
/// primitive, never shared scratch.
class Splitter {
public:
    explicit Splitter(BuildContext& ctx) : ctx_(ctx) {}
    virtual ~Splitter() = default;
    /// Chooses a split and reorders the range so the left child's primitives come first; returns
    /// a leaf (left_count 0) when no split exists or the SAH prefers a leaf and count <= max_leaf.
    /// `threads` may be used for a node of kParallelNodeSize primitives or more; the result must
    /// not depend on it.
    virtual Split split(const NodeRange& node, unsigned threads) = 0;
    /// Always splits a range of count >= 2 in two halves by count (object median on the widest
    /// centroid axis); used when no good split exists but the node is too big, and past
    /// kMaxSahDepth to bound the depth.
    virtual Split median_split(const NodeRange& node);

protected:
    BuildContext& ctx_;
};

/// The split of a node of at most kBlockPackMax primitives when options.sah_block is above 1
/// (block_builder.cpp): a full SAH sweep on each axis whose planes leave a multiple of sah_block
/// on the left (any plane when the node holds no more than one block), so that every leaf below
/// but one is full. Reorders the range like Splitter::split; a leaf (left_count 0) when the SAH
/// prefers one and count <= max_leaf. Past kMaxSahDepth it halves the node on a block boundary.
Split block_split(BuildContext& ctx, const NodeRange& node, uint32_t depth);

std::unique_ptr<Splitter> make_midpoint_splitter(BuildContext& ctx);
std::unique_ptr<Splitter> make_binned_sah_splitter(BuildContext& ctx);
std::unique_ptr<Splitter> make_sweep_sah_splitter(BuildContext& ctx);
std::unique_ptr<Splitter> make_lbvh_splitter(BuildContext& ctx);

/// The spatial-split builder (sbvh_builder.cpp): not a Splitter, since its nodes' references are
/// not ranges of one permutation (a primitive may sit in several leaves). One thread, the same
/// tree for any options.threads; child-order centroid bits and optimizers are applied after.
BvhData build_sbvh(const BuildPrimitives& prims, const BvhBuildOptions& options);

}  // namespace thicket::bvh_build
