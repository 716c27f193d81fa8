// SBVH builder (Stich, Friedrich & Dietrich 2009, "Spatial splits in bounding volume
// hierarchies"): at each node the best object split (over the references' centroids: binned in
// big nodes, a full SAH sweep in small ones) competes with the best spatial split, a plane through the node's box
// that cuts the references straddling it in two, each part clipped exactly to its side
// (clip_triangle_to_box, the kD-tree's perfect-split clipper, through BuildPrimitives::clip). A
// primitive may then sit in several leaves: the index array holds more entries than primitives.
//
// Spatial splits are tried only where they can pay: when the object split's children overlap by
// more than alpha times the root's surface area. The replication budget (at most (1 + budget) N
// references) is handed down the tree: each node's share of what is left goes to its children in
// proportion to their references, so the tree does not depend on the order nodes are built in.
//
// One thread, depth first with an explicit stack (depth is bounded by memory, not the C stack):
// the tree is the same for every thread count. Leaves are written in depth-first order, so every
// subtree's references are one contiguous range of the index array, as with the other builders
// (bvh8's collapse and the reinsertion optimizer rely on it).
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <vector>

#include "splitter.h"
#include "thicket/core/error.h"

namespace thicket::bvh_build {
namespace {

/// Spatial bins per axis: Stich et al. and Embree use 16-32. Each straddling reference is clipped
/// once per bin it crosses, which is most of the build: on Sponza, bvh8:quality=high took 4.1 s
/// for an Embree-metric SAH of 18.21 with 32 bins, 2.2 s for 18.08 with 16 (docs/bvh8.md).
constexpr uint32_t kSpatialBins = 16;

/// Object splits of nodes of more references than kSweepMax are binned (kObjectBins centroid
/// bins per axis, one pass), smaller ones swept in full: a sort per node of every size made the
/// build O(N log^2 N), seconds on the dragon, for a tree barely better at the top levels.
constexpr uint32_t kSweepMax = 256;
constexpr uint32_t kObjectBins = 64;

/// One reference: a primitive, or the part of it inside a region, with that part's bounds.
struct Ref {
    Aabb box;
    uint32_t prim;
};

/// A node still to be split: its slot in the pool, depth, references, and how many references
/// its subtree may still add by spatial splits.
struct Task {
    uint32_t node = 0;
    uint32_t depth = 0;
    uint64_t extra = 0;
    std::vector<Ref> refs;
};

/// The best split found of one kind.
struct Candidate {
    float cost = kInfinity;
    int axis = -1;
    uint32_t position = 0;  ///< swept object split: left count in axis order; binned: the plane's index
    bool binned = false;    ///< a binned object split: lo and scale place each centroid in its bin
    float lo = 0.0f, scale = 0.0f;
};

class SbvhBuilder {
public:
    SbvhBuilder(const BuildPrimitives& prims, const BvhBuildOptions& options) : prims_(prims), options_(options) {}

    /// The whole build: a BVH whose leaves list references (primitive ids, some repeated).
    BvhData run() {
        const uint32_t n = uint32_t(prims_.bounds.size());
        BvhData bvh;
        if (n == 0) return bvh;
        // The budget, as a count: at most (1 + budget) n references, and never more than the
        // validator accepts (kMaxReferencesPerPrimitive per primitive).
        const double budget = options_.sbvh_budget > 0.0  // NaN: none
                                  ? std::min(options_.sbvh_budget, double(kMaxReferencesPerPrimitive - 1))
                                  : 0.0;
        const uint64_t extra = uint64_t(std::floor(budget * double(n)));
        Task root;
        root.extra = extra;
        root.refs.resize(n);
        for (uint32_t i = 0; i < n; ++i) root.refs[i] = {prims_.bounds[i], i};
        Aabb root_box;
        for (const Ref& r : root.refs) root_box.grow(r.box);
        root_half_area_ = root_box.half_area();

        // A pool of 2 (n + extra) nodes holds any tree over n + extra references (slot 1 unused).
        const size_t pool = 2 * (size_t(n) + size_t(extra));
        bvh.nodes.reserve(pool);
        bvh.child_order.reserve(pool);
        bvh.nodes.resize(2);
        bvh.child_order.assign(2, 0);
        bvh.prim_indices.reserve(size_t(n) + size_t(extra));
        bvh.nodes_used = 2;

        std::vector<Task> stack;
        stack.push_back(std::move(root));
        while (!stack.empty()) {
            Task task = std::move(stack.back());
            stack.pop_back();
            BvhNode& node = bvh.nodes[task.node];
            Aabb box;
            for (const Ref& r : task.refs) box.grow(r.box);
            node.aabbMin = box.min;
            node.aabbMax = box.max;

            std::vector<Ref> left, right;
            int axis = 0;
            if (!split(task, box, left, right, axis)) {
                node.leftFirst = uint32_t(bvh.prim_indices.size());
                node.count = uint32_t(task.refs.size());
                for (const Ref& r : task.refs) bvh.prim_indices.push_back(r.prim);
                continue;
            }
            const uint32_t l = bvh.nodes_used;
            bvh.nodes_used += 2;
            bvh.nodes.resize(bvh.nodes_used);
            bvh.child_order.resize(bvh.nodes_used);
            BvhNode& parent = bvh.nodes[task.node];  // resize may have moved it
            parent.leftFirst = l;
            parent.count = 0;
            bvh.child_order[task.node] = ChildOrder::pack(axis, 0, false);

            // What the node may still add goes to its children in proportion to their references.
            const uint64_t added = left.size() + right.size() - task.refs.size();
            const uint64_t remaining = task.extra - added;
            const uint64_t left_share = remaining * left.size() / (left.size() + right.size());
            Task lt{l, task.depth + 1, left_share, std::move(left)};
            Task rt{l + 1, task.depth + 1, remaining - left_share, std::move(right)};
            std::vector<Ref>().swap(task.refs);
            stack.push_back(std::move(rt));  // left on top: leaves come out in depth-first order
            stack.push_back(std::move(lt));
        }
        return bvh;
    }

private:
    /// Bounds of the part of primitive `prim` inside `box`.
    Aabb clip(uint32_t prim, const Aabb& box) const {
        if (prims_.clip) return prims_.clip(prim, box);
        return intersection(prims_.bounds[prim], box);
    }

    /// Splits task.refs (whose bounds are `box`) into `left` and `right`, or returns false to
    /// make a leaf: a node of one reference, or of at most max_leaf whose best split costs more
    /// than the leaf. Past kMaxSahDepth, object medians only, which halve the count: the depth
    /// stays bounded whatever spatial splits did above.
    bool split(const Task& task, const Aabb& box, std::vector<Ref>& left, std::vector<Ref>& right, int& axis) {
        const std::vector<Ref>& refs = task.refs;
        const uint32_t n = uint32_t(refs.size());
        if (n <= 1) return false;
        if (task.depth >= kMaxSahDepth) {
            median_split(refs, left, right, axis);
            return true;
        }
        const float half_area = box.half_area();
        Aabb object_left, object_right;
        // A small node's object splits leave whole blocks on the left (BvhBuildOptions::sah_block).
        // Its spatial splits are left free: held to the same rule (by their binned counts) they
        // filled no more blocks and raised bvh8:quality=high's Embree SAH 0.05-0.3% on sibenik,
        // sponza and the teapot.
        const uint32_t block = options_.sah_block;
        aligned_ = block > 1 && n <= kBlockPackMax && n > block;
        const Candidate object = object_split(refs, half_area, object_left, object_right);
        Candidate spatial;
        // Stich et al.'s test: a spatial split can only help where the object split's children
        // overlap; alpha of the root's area keeps the search to the nodes where that matters.
        const float overlap = intersection(object_left, object_right).half_area();
        if (task.extra > 0 && double(overlap) > options_.sbvh_alpha * double(root_half_area_))
            spatial = spatial_split(refs, box, half_area, task.extra);
        const float best = std::min(object.cost, spatial.cost);
        const bool may_stop = n <= uint32_t(options_.max_leaf);
        if (may_stop && !(best < sah_leaf_cost(n, block))) return false;  // NaN costs (NaN boxes) too
        if (spatial.cost < object.cost && apply_spatial(refs, box, spatial, task.extra, left, right)) {
            axis = spatial.axis;
            return true;
        }
        if (object.axis < 0) {  // no finite cost (NaN boxes) but too big a leaf: halve it
            median_split(refs, left, right, axis);
            return true;
        }
        apply_object(refs, object, left, right);
        axis = object.axis;
        return true;
    }

    /// The sort key of a reference on `axis`: its box's centroid (doubled: the order is what
    /// counts); NaN last so the order is total.
    static float key(const Ref& r, int axis) {
        const float k = r.box.min[axis] + r.box.max[axis];
        return std::isnan(k) ? kInfinity : k;
    }

    /// Sorts order_ (0..n-1) by key on `axis`, ties by primitive id: references of one node are
    /// of distinct primitives (a cut reference's parts go to different children), so the order,
    /// and the tree, never depend on the sort's implementation.
    void sort_axis(const std::vector<Ref>& refs, int axis) {
        const uint32_t n = uint32_t(refs.size());
        keys_.resize(n);
        order_.resize(n);
        for (uint32_t i = 0; i < n; ++i) keys_[i] = key(refs[i], axis);
        std::iota(order_.begin(), order_.end(), 0u);
        std::sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
            return keys_[a] < keys_[b] || (keys_[a] == keys_[b] && refs[a].prim < refs[b].prim);
        });
    }

    /// Bin of a centroid key among `bins`; NaN and out-of-range values clamp.
    static uint32_t key_bin(float k, float lo, float scale, uint32_t bins) {
        const float f = (k - lo) * scale;
        if (!(f > 0.0f)) return 0;
        return f < float(bins) ? std::min(uint32_t(f), bins - 1) : bins - 1;
    }

    /// The best object split of a big node: centroid keys binned on each axis (Wald 2007);
    /// also its children's bounds.
    Candidate binned_object_split(const std::vector<Ref>& refs, float half_area, Aabb& best_left, Aabb& best_right) {
        Candidate best;
        std::array<Aabb, kObjectBins> best_bins;
        for (int axis = 0; axis < 3; ++axis) {
            float lo = kInfinity, hi = -kInfinity;
            for (const Ref& r : refs) {
                const float k = key(r, axis);
                lo = std::min(lo, k);
                hi = std::max(hi, k);
            }
            const float extent = hi - lo;
            if (!(extent > 0.0f) || !std::isfinite(extent)) continue;
            const float scale = float(kObjectBins) / extent;
            std::array<Aabb, kObjectBins> bins;
            std::array<uint32_t, kObjectBins> counts{};
            for (const Ref& r : refs) {
                const uint32_t b = key_bin(key(r, axis), lo, scale, kObjectBins);
                bins[b].grow(r.box);
                ++counts[b];
            }
            std::array<float, kObjectBins> right_area;
            std::array<uint32_t, kObjectBins> right_count;
            sah_sweep(
                kObjectBins, [&](uint32_t b) -> const Aabb& { return bins[b]; }, [&](uint32_t b) { return counts[b]; },
                [&](uint32_t b) { return counts[b]; }, half_area, options_.sah_block, right_area.data(),
                right_count.data(), [&](uint32_t p, float cost, uint32_t, uint32_t) {
                    if (cost < best.cost) {
                        best = {cost, axis, p, true, lo, scale};
                        best_bins = bins;
                    }
                });
        }
        if (best.axis < 0) return best;
        best_left = best_right = Aabb{};
        for (uint32_t b = 0; b < kObjectBins; ++b) (b <= best.position ? best_left : best_right).grow(best_bins[b]);
        return best;
    }

    /// The best object split: binned above kSweepMax references, else by a full SAH sweep on
    /// each axis; also its children's bounds.
    Candidate object_split(const std::vector<Ref>& refs, float half_area, Aabb& best_left, Aabb& best_right) {
        const uint32_t n = uint32_t(refs.size());
        if (n > kSweepMax) {
            const Candidate binned = binned_object_split(refs, half_area, best_left, best_right);
            if (binned.axis >= 0) return binned;  // else all centroids coincide: the sweep splits by id
        }
        Candidate best;
        right_area_.resize(n);
        right_count_.resize(n);
        for (int axis = 0; axis < 3; ++axis) {
            sort_axis(refs, axis);
            bool improved = false;
            // Plane p puts order_[0..p] on the left.
            sah_sweep(
                n, [&](uint32_t k) -> const Aabb& { return refs[order_[k]].box; }, [](uint32_t) { return 1u; },
                [](uint32_t) { return 1u; }, half_area, options_.sah_block, right_area_.data(), right_count_.data(),
                [&](uint32_t p, float cost, uint32_t left, uint32_t) {
                    if (aligned_ && left % options_.sah_block != 0) return;
                    if (cost < best.cost) {
                        best = {cost, axis, p + 1};
                        improved = true;
                    }
                });
            if (improved) best_order_.swap(order_);  // kept for apply_object: no sort again
        }
        if (best.axis < 0) return best;
        best_left = best_right = Aabb{};
        for (uint32_t k = 0; k < n; ++k) (k < best.position ? best_left : best_right).grow(refs[best_order_[k]].box);
        return best;
    }

    /// The object split object_split() found last: binned, the references whose centroid falls
    /// in a bin up to `position`; swept, the first `position` references in its axis order.
    void apply_object(const std::vector<Ref>& refs, const Candidate& c, std::vector<Ref>& left, std::vector<Ref>& right) {
        if (c.binned) {
            for (const Ref& r : refs)
                (key_bin(key(r, c.axis), c.lo, c.scale, kObjectBins) <= c.position ? left : right).push_back(r);
            return;
        }
        left.reserve(c.position);
        right.reserve(refs.size() - c.position);
        for (uint32_t k = 0; k < refs.size(); ++k) (k < c.position ? left : right).push_back(refs[best_order_[k]]);
    }

    /// Halves the references by centroid order on the axis of widest centroid spread.
    void median_split(const std::vector<Ref>& refs, std::vector<Ref>& left, std::vector<Ref>& right, int& axis) {
        Aabb cb;
        for (const Ref& r : refs) cb.grow(r.box.center());
        axis = cb.empty() ? 0 : max_axis(cb.extent());
        sort_axis(refs, axis);
        const uint32_t half = uint32_t(refs.size() / 2);
        for (uint32_t k = 0; k < refs.size(); ++k) (k < half ? left : right).push_back(refs[order_[k]]);
    }

    /// The node's box cut into kSpatialBins slabs on `axis`: the plane after bin p.
    static float plane(const Aabb& box, int axis, uint32_t p) {
        const float lo = box.min[axis], extent = box.max[axis] - lo;
        return lo + extent * (float(p + 1) / float(kSpatialBins));
    }

    /// Bin of coordinate x; NaN and out-of-range values clamp.
    static uint32_t bin_of(float x, float lo, float scale) {
        const float f = (x - lo) * scale;
        if (!(f > 0.0f)) return 0;
        return f < float(kSpatialBins) ? std::min(uint32_t(f), kSpatialBins - 1) : kSpatialBins - 1;
    }

    /// The best spatial split: per axis, references are binned by where they start and end, each
    /// straddling one clipped to every bin it crosses; the SAH of each plane between bins counts
    /// the references starting left of it and those ending right of it. Planes that would add
    /// more references than `extra` allows are skipped.
    Candidate spatial_split(const std::vector<Ref>& refs, const Aabb& box, float half_area, uint64_t extra) {
        Candidate best;
        const uint32_t n = uint32_t(refs.size());
        for (int axis = 0; axis < 3; ++axis) {
            const float lo = box.min[axis], extent = box.max[axis] - lo;
            if (!(extent > 0.0f) || !std::isfinite(extent)) continue;
            const float scale = float(kSpatialBins) / extent;
            std::array<Aabb, kSpatialBins> bins;
            std::array<uint32_t, kSpatialBins> entries{}, exits{};
            for (const Ref& r : refs) {
                const uint32_t b0 = bin_of(r.box.min[axis], lo, scale);
                const uint32_t b1 = std::max(b0, bin_of(r.box.max[axis], lo, scale));
                ++entries[b0];
                ++exits[b1];
                if (b0 == b1) {
                    bins[b0].grow(r.box);
                    continue;
                }
                for (uint32_t b = b0; b <= b1; ++b) {
                    Aabb slab = r.box;
                    if (b > b0) slab.min[axis] = plane(box, axis, b - 1);
                    if (b < b1) slab.max[axis] = plane(box, axis, b);
                    bins[b].grow(clip(r.prim, slab));
                }
            }
            std::array<float, kSpatialBins> right_area;
            std::array<uint32_t, kSpatialBins> right_count;
            sah_sweep(
                kSpatialBins, [&](uint32_t b) -> const Aabb& { return bins[b]; }, [&](uint32_t b) { return entries[b]; },
                [&](uint32_t b) { return exits[b]; }, half_area, options_.sah_block, right_area.data(),
                right_count.data(), [&](uint32_t p, float cost, uint32_t left, uint32_t right) {
                    if (uint64_t(left) + right > uint64_t(n) + extra) return;  // over budget
                    if (cost < best.cost) best = {cost, axis, p};
                });
        }
        return best;
    }

    /// Cuts the references at the chosen plane: those wholly on one side go there, those
    /// straddling it are clipped to each side. Returns false (nothing changed) when a side ends
    /// up empty or the cut would exceed `extra`: binning estimated the counts with its own
    /// rounding, the partition is exact.
    bool apply_spatial(const std::vector<Ref>& refs, const Aabb& box, const Candidate& c, uint64_t extra,
                       std::vector<Ref>& left, std::vector<Ref>& right) {
        const int axis = c.axis;
        const float pos = plane(box, axis, c.position);
        for (const Ref& r : refs) {
            const float lo = r.box.min[axis], hi = r.box.max[axis];
            if (hi <= pos) {
                left.push_back(r);
            } else if (lo < pos && hi > pos) {
                Aabb lb = r.box, rb = r.box;
                lb.max[axis] = pos;
                rb.min[axis] = pos;
                const Aabb lc = clip(r.prim, lb), rc = clip(r.prim, rb);
                if (!lc.empty()) left.push_back({lc, r.prim});
                if (!rc.empty()) right.push_back({rc, r.prim});
                if (lc.empty() && rc.empty()) left.push_back(r);  // rounding lost both: keep it whole
            } else {
                right.push_back(r);  // lo >= pos, or NaN bounds (never hit, anywhere will do)
            }
        }
        if (left.empty() || right.empty() || left.size() + right.size() > refs.size() + extra) {
            left.clear();
            right.clear();
            return false;
        }
        return true;
    }

    const BuildPrimitives& prims_;
    const BvhBuildOptions& options_;
    float root_half_area_ = 0.0f;
    bool aligned_ = false;  ///< the node being split takes only planes with whole blocks on the left
    std::vector<float> keys_, right_area_;
    std::vector<uint32_t> right_count_;
    std::vector<uint32_t> order_, best_order_;  ///< the axis being swept; the best axis's order
};

}  // namespace

BvhData build_sbvh(const BuildPrimitives& prims, const BvhBuildOptions& options) {
    return SbvhBuilder(prims, options).run();
}

}  // namespace thicket::bvh_build
