#pragma once
// Internal to the BVH builders: the one thing a builder decides is how to split a node.
#include <memory>
#include <vector>

#include "thicket/bvh/build.h"
#include "thicket/core/ray.h"
#include "thicket/core/sah.h"

namespace thicket::bvh_build {

struct NodeRange {
    uint32_t first = 0, count = 0;
    Aabb bounds;  ///< of the primitives' bounds in the range
};

/// left_count == 0 means "make a leaf"; otherwise indices[first, first+left_count) is the left child.
struct Split {
    uint32_t left_count = 0;
    int axis = 0;  ///< the left child lies on the lower side of this axis
};

struct BuildContext {
    BuildPrimitives prims;
    std::vector<uint32_t>& indices;
    BvhBuildOptions options;
};

/// SAH cost of a split relative to its parent; a degenerate (zero-area) parent makes every
/// split cost more than the leaf, so only max_leaf forces one.
inline float sah_split_cost(float left_half_area, uint32_t left_count, float right_half_area, uint32_t right_count,
                            float parent_half_area) {
    if (!(parent_half_area > 0.0f)) return kSahTraversalCost + kSahIntersectionCost * float(left_count + right_count);
    return kSahTraversalCost +
           kSahIntersectionCost * (left_half_area * float(left_count) + right_half_area * float(right_count)) /
               parent_half_area;
}

inline float sah_leaf_cost(uint32_t count) { return kSahIntersectionCost * float(count); }

/// Bounds of the centroids of indices[first, first+count).
Aabb centroid_bounds(const BuildContext& ctx, const NodeRange& node);

class Splitter {
public:
    explicit Splitter(BuildContext& ctx) : ctx_(ctx) {}
    virtual ~Splitter() = default;
    /// Chooses a split and reorders the range so the left child's primitives come first; returns
    /// a leaf (left_count 0) when no split exists or the SAH prefers a leaf and count <= max_leaf.
    virtual Split split(const NodeRange& node) = 0;
    /// Always splits a range of count >= 2 in two halves by count (object median on the widest
    /// centroid axis); used when no good split exists but the node is too big, and past
    /// kMaxSahDepth to bound the depth.
    virtual Split median_split(const NodeRange& node);

protected:
    BuildContext& ctx_;
};

std::unique_ptr<Splitter> make_midpoint_splitter(BuildContext& ctx);
std::unique_ptr<Splitter> make_binned_sah_splitter(BuildContext& ctx);
std::unique_ptr<Splitter> make_sweep_sah_splitter(BuildContext& ctx);

}  // namespace thicket::bvh_build
