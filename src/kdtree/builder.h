#pragma once
// Internal to the kD-tree builders: appending nodes depth first, and the two builders.
#include <span>
#include <string>

#include "thicket/core/error.h"
#include "thicket/kdtree/build.h"

namespace thicket::kd_build {

/// Appends nodes in depth-first order: an interior node, then its whole below subtree, then
/// its above subtree (whose index is patched into the interior node).
class TreeWriter {
public:
    explicit TreeWriter(KdTreeData& tree) : tree_(tree) {}

    /// Appends a leaf referencing `prims`.
    void leaf(std::span<const uint32_t> prims) {
        check_room();
        const size_t first = tree_.prim_indices.size();
        if (prims.size() > kKdMaxField || first + prims.size() > 0xFFFFFFFFu)
            throw Error("kdtree: " + std::to_string(first + prims.size()) +
                        " primitive references do not fit the 8-byte node's fields");
        tree_.prim_indices.insert(tree_.prim_indices.end(), prims.begin(), prims.end());
        tree_.nodes.push_back(KdNode::leaf(uint32_t(first), uint32_t(prims.size())));
    }
    /// Appends an interior node; its below child must be appended next. Returns its index.
    uint32_t interior(int axis, float split) {
        check_room();
        tree_.nodes.push_back(KdNode::interior(axis, split, 0));
        return uint32_t(tree_.nodes.size() - 1);
    }
    /// Call once the below subtree of `node` is complete: the above child comes next.
    void start_above(uint32_t node) {
        KdNode& n = tree_.nodes[node];
        n = KdNode::interior(n.axis(), n.split(), uint32_t(tree_.nodes.size()));
    }

private:
    void check_room() const {
        if (tree_.nodes.size() >= kKdMaxField)
            throw Error("kdtree: more than " + std::to_string(kKdMaxField) + " nodes do not fit the 8-byte node");
    }
    KdTreeData& tree_;
};

/// Both builders take the primitives to place (finite bounds), the root voxel and the depth limit.
void build_sah(const KdBuildInput& input, const KdCostModel& cost, uint32_t max_depth,
               std::span<const uint32_t> prims, const Aabb& root, TreeWriter& out);
void build_median(const KdBuildInput& input, const KdCostModel& cost, uint32_t max_depth,
                  std::span<const uint32_t> prims, const Aabb& root, TreeWriter& out);

}  // namespace thicket::kd_build
