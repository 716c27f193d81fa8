// The simple kD-tree builder: split the voxel's longest axis in the middle, as long as the SAH
// says the split pays (the same cost model as the SAH builder, so only the choice of planes
// differs). Straddling primitives are clipped to the child voxels like in the SAH builder.
#include <vector>

#include "builder.h"

namespace thicket::kd_build {
namespace {

struct Ref {
    uint32_t prim;
    Aabb box;  ///< bounds of the part of the primitive inside the current voxel
};

class MedianBuilder {
public:
    MedianBuilder(const KdBuildInput& input, const KdCostModel& cost, uint32_t max_depth, TreeWriter& out)
        : input_(input), cost_(cost), max_depth_(max_depth), out_(out) {}

    void build(std::span<const uint32_t> prims, const Aabb& root) {
        std::vector<Ref> refs;
        refs.reserve(prims.size());
        for (uint32_t p : prims) refs.push_back({p, input_.bounds[p]});
        // Depth first with an explicit stack (left child first, as the tree is written).
        std::vector<Task> stack;
        stack.push_back({std::move(refs), root, 0, kNoAbove});
        while (!stack.empty()) {
            Task task = std::move(stack.back());
            stack.pop_back();
            if (task.above != kNoAbove) out_.start_above(task.above);
            node(std::move(task.refs), task.voxel, task.depth, stack);
        }
    }

private:
    static constexpr uint32_t kNoAbove = ~0u;
    /// A subtree still to build; `above` is its parent when it is a right child.
    struct Task {
        std::vector<Ref> refs;
        Aabb voxel;
        uint32_t depth, above;
    };

    /// Writes the node of `refs` in `voxel`: a leaf, or an interior node whose children it pushes.
    void node(std::vector<Ref> refs, const Aabb& voxel, uint32_t depth, std::vector<Task>& stack) {
        const int axis = max_axis(voxel.extent());
        const float pos = voxel.center()[axis];
        uint32_t nl = 0, np = 0, nr = 0;
        for (const Ref& r : refs) {
            nl += r.box.min[axis] < pos;
            nr += r.box.max[axis] > pos;
            np += r.box.min[axis] == pos && r.box.max[axis] == pos;
        }
        KdPlaneCost c;
        const auto count = uint32_t(refs.size());
        if (count == 0 || depth >= max_depth_ || !kd_plane_cost(cost_, voxel, axis, pos, nl, np, nr, c) ||
            !(c.cost < kd_leaf_cost(cost_, count))) {
            leaf_.clear();
            for (const Ref& r : refs) leaf_.push_back(r.prim);
            out_.leaf(leaf_);
            return;
        }
        Aabb left_voxel = voxel, right_voxel = voxel;
        left_voxel.max[axis] = pos;
        right_voxel.min[axis] = pos;
        std::vector<Ref> left, right;
        for (const Ref& r : refs) {
            const float lo = r.box.min[axis], hi = r.box.max[axis];
            const bool planar = lo == hi;
            if (planar ? (lo < pos || (lo == pos && c.planar_left)) : hi <= pos) {
                left.push_back(r);
            } else if (planar ? true : lo >= pos) {
                right.push_back(r);
            } else {  // straddles the plane: perfect split
                const Aabb lb = input_.clip(r.prim, left_voxel), rb = input_.clip(r.prim, right_voxel);
                if (!lb.empty()) left.push_back({r.prim, lb});
                if (!rb.empty()) right.push_back({r.prim, rb});
            }
        }
        std::vector<Ref>().swap(refs);
        const uint32_t me = out_.interior(axis, pos);
        stack.push_back({std::move(right), right_voxel, depth + 1, me});
        stack.push_back({std::move(left), left_voxel, depth + 1, kNoAbove});
    }

    const KdBuildInput& input_;
    const KdCostModel cost_;
    const uint32_t max_depth_;
    TreeWriter& out_;
    std::vector<uint32_t> leaf_;
};

}  // namespace

void build_median(const KdBuildInput& input, const KdCostModel& cost, uint32_t max_depth,
                  std::span<const uint32_t> prims, const Aabb& root, TreeWriter& out) {
    MedianBuilder(input, cost, max_depth, out).build(prims, root);
}

}  // namespace thicket::kd_build
