// BIH construction (Wächter & Keller 2006, "Instant ray tracing: the bounding interval
// hierarchy"): the global heuristic over a candidate box that is halved at every level whatever
// the objects' bounds are, an in-place partition of the index array per node, and the depth
// bound that keeps the fixed traversal stack safe.
#include <algorithm>
#include <numeric>
#include <string>

#include "thicket/bih/build.h"
#include "thicket/core/error.h"
#include "thicket/core/ray.h"

namespace thicket {

namespace {

/// The candidate plane: the middle of [lo, hi], never outside it (no overflow near FLT_MAX).
float midpoint(float lo, float hi) { return std::clamp(0.5f * lo + 0.5f * hi, lo, hi); }

/// Fraction of a node's extent on the split axis that an empty child must cut off before the
/// Cut mode spends a node on it; smaller cuts gain less than the extra node costs.
constexpr float kMinEmptyCut = 0.25f;

struct Task {
    uint32_t node, first, count, depth;
    Aabb candidate;  ///< the global heuristic's box: split candidates are its midpoints
    Aabb box;        ///< the node's own box: the parent's box clipped by the node's plane
};

class Builder {
public:
    Builder(std::span<const Aabb> bounds, const BihBuildOptions& options, BihData& bih)
        : bounds_(bounds), options_(options), bih_(bih), centers_(bounds.size()) {
        for (size_t i = 0; i < bounds.size(); ++i)
            for (int a = 0; a < 3; ++a) centers_[i][a] = midpoint(bounds[i].min[a], bounds[i].max[a]);
    }

    void run() {
        const uint32_t n = uint32_t(bounds_.size());
        bih_.nodes.push_back(BihNode::leaf(0, n));
        std::vector<Task> stack{{0, 0, n, 0, bih_.bounds, bih_.bounds}};
        while (!stack.empty()) {
            const Task task = stack.back();
            stack.pop_back();
            split(task, stack);
        }
    }

private:
    /// Makes task.node a leaf or an inner node, pushing the children's tasks.
    void split(Task task, std::vector<Task>& stack) {
        if (task.count <= uint32_t(options_.max_leaf)) {
            bih_.nodes[task.node] = BihNode::leaf(task.first, task.count);
            return;
        }
        Aabb centers, objects;
        for (uint32_t i = task.first; i < task.first + task.count; ++i) {
            centers.grow(centers_[indices()[i]]);
            objects.grow(bounds_[indices()[i]]);
        }
        const bool separable = centers.min != centers.max;
        if (!separable || task.depth >= kBihMaxSpatialDepth) {
            count_split(task, centers, stack);
            return;
        }
        // The global heuristic: halve the candidate box until its plane separates the centres.
        while (true) {
            const int axis = max_axis(task.candidate.extent());
            const float plane = midpoint(task.candidate.min[axis], task.candidate.max[axis]);
            const bool all_left = centers.max[axis] < plane, all_right = centers.min[axis] >= plane;
            if (!all_left && !all_right) {
                plane_split(task, axis, plane, stack);
                return;
            }
            const Aabb before = task.candidate;
            (all_left ? task.candidate.max : task.candidate.min)[axis] = plane;
            if (task.candidate.min == before.min && task.candidate.max == before.max) {
                // The candidate box cannot shrink any more (its extent is down to one ulp).
                count_split(task, centers, stack);
                return;
            }
            if (options_.empty_side == BihEmptySide::Cut && cut_empty_side(task, axis, all_left, objects, stack)) return;
        }
    }

    /// In Cut mode, when the objects leave at least kMinEmptyCut of the node's extent empty on
    /// `axis` (on the side the candidate plane found empty), makes the node an inner node with an
    /// empty child there and continues with the other child. Returns whether it did.
    bool cut_empty_side(const Task& task, int axis, bool all_left, const Aabb& objects, std::vector<Task>& stack) {
        const float extent = task.box.max[axis] - task.box.min[axis];
        const float gap = all_left ? task.box.max[axis] - objects.max[axis] : objects.min[axis] - task.box.min[axis];
        if (!(gap >= kMinEmptyCut * extent) || !(extent > 0.0f) || cut_nodes_ >= bounds_.size()) return false;
        ++cut_nodes_;
        const uint32_t left = allocate_pair();
        Task child = task;
        child.depth = task.depth + 1;
        if (all_left) {
            bih_.nodes[task.node] = BihNode::inner(axis, left, objects.max[axis], kInfinity);
            bih_.nodes[left + 1] = BihNode::leaf(0, 0);
            child.node = left;
            child.box.max[axis] = objects.max[axis];
        } else {
            bih_.nodes[task.node] = BihNode::inner(axis, left, -kInfinity, objects.min[axis]);
            bih_.nodes[left] = BihNode::leaf(0, 0);
            child.node = left + 1;
            child.box.min[axis] = objects.min[axis];
        }
        stack.push_back(child);
        return true;
    }

    /// Partitions the range in place by centre against `plane` (QuickSort-like) and makes the node
    /// an inner node whose clip planes are the two sides' actual extremes.
    void plane_split(const Task& task, int axis, float plane, std::vector<Task>& stack) {
        auto begin = indices().begin() + task.first, end = begin + task.count;
        const auto mid = std::partition(begin, end, [&](uint32_t i) { return centers_[i][axis] < plane; });
        Task left = task, right = task;
        left.candidate.max[axis] = plane;
        right.candidate.min[axis] = plane;
        make_inner(task, axis, uint32_t(mid - begin), left, right, stack);
    }

    /// Splits a range whose centres no plane separates (all equal, or too deep for the global
    /// heuristic) in two halves by count along the centres' widest axis.
    void count_split(const Task& task, const Aabb& centers, std::vector<Task>& stack) {
        const int axis = max_axis(centers.extent());
        auto begin = indices().begin() + task.first;
        const uint32_t half = task.count / 2;
        // Ties broken by index so the result does not depend on the library's nth_element.
        std::nth_element(begin, begin + half, begin + task.count, [&](uint32_t a, uint32_t b) {
            return centers_[a][axis] < centers_[b][axis] || (centers_[a][axis] == centers_[b][axis] && a < b);
        });
        make_inner(task, axis, half, task, task, stack);
    }

    /// Writes the inner node for a range already partitioned at first + left_count and pushes
    /// both children; the clip planes come from the primitives' bounds on either side.
    void make_inner(const Task& task, int axis, uint32_t left_count, Task left, Task right, std::vector<Task>& stack) {
        float left_max = -kInfinity, right_min = kInfinity;
        for (uint32_t i = task.first; i < task.first + left_count; ++i)
            left_max = std::max(left_max, bounds_[indices()[i]].max[axis]);
        for (uint32_t i = task.first + left_count; i < task.first + task.count; ++i)
            right_min = std::min(right_min, bounds_[indices()[i]].min[axis]);
        const uint32_t child = allocate_pair();
        bih_.nodes[task.node] = BihNode::inner(axis, child, left_max, right_min);
        left.node = child;
        left.count = left_count;
        left.depth = task.depth + 1;
        left.box.max[axis] = std::min(task.box.max[axis], left_max);
        right.node = child + 1;
        right.first = task.first + left_count;
        right.count = task.count - left_count;
        right.depth = task.depth + 1;
        right.box.min[axis] = std::max(task.box.min[axis], right_min);
        stack.push_back(right);
        stack.push_back(left);
    }

    uint32_t allocate_pair() {
        const size_t first = bih_.nodes.size();
        if (first + 2 > kBihMaxIndex) throw Error("build_bih: more than 2^30 nodes");
        bih_.nodes.resize(first + 2);
        return uint32_t(first);
    }

    std::vector<uint32_t>& indices() { return bih_.prim_indices; }

    std::span<const Aabb> bounds_;
    BihBuildOptions options_;
    BihData& bih_;
    std::vector<Vec3> centers_;
    size_t cut_nodes_ = 0;  ///< at most one per primitive, so nodes stay below 4N
};

}  // namespace

BihData build_bih(std::span<const Aabb> bounds, const BihBuildOptions& options) {
    if (bounds.size() > kBihMaxIndex) throw Error("build_bih: more than 2^30 primitives");
    if (options.max_leaf < 1) throw Error("build_bih: max-leaf=" + std::to_string(options.max_leaf) + " must be >= 1");
    BihData bih;
    bih.prim_indices.resize(bounds.size());
    std::iota(bih.prim_indices.begin(), bih.prim_indices.end(), 0u);
    for (const Aabb& b : bounds) bih.bounds.grow(b);
    if (bounds.empty()) return bih;
    bih.nodes.reserve(2 * bounds.size());
    Builder(bounds, options, bih).run();
    return bih;
}

}  // namespace thicket
