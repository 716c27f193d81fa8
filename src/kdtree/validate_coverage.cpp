// What kD-tree traversal relies on beyond the tree's structure: every leaf lists every primitive
// that reaches its cell. A tree that merely is well formed can still leave a primitive out of
// a leaf (a flipped bit in a split plane or a primitive index); a saved tree like that answered
// 2 of 6,144 rays unlike brute force. The proof replays the builders' own classification (the
// rules of median_builder.cpp and sah_builder.cpp, which agree) over the stored splits: a
// primitive whose (clipped) box lies below the plane goes below, above goes above, one that
// straddles it is clipped to both child cells, exactly as the builder clipped it.
#include <algorithm>
#include <cmath>

#include "thicket/core/error.h"
#include "thicket/kdtree/build.h"

namespace thicket {

namespace {

struct Ref {
    uint32_t prim;
    Aabb box;
};

/// How a child's reference serves its parent's: a primitive on one side, or clipped to both
/// (both copies must be listed), or flat in the split plane (the builder put it on one side of
/// its choosing, not recorded in the tree: either copy being listed will do).
enum class Via : uint8_t { One, Both, Either };

class CoverageCheck {
public:
    CoverageCheck(const KdTreeData& tree, const KdBuildInput& input)
        : tree_(tree), input_(input), mark_(input.bounds.size(), uint32_t(-1)) {}

    /// Which of `refs` are not listed in every leaf they reach below node i (1 = missing).
    std::vector<uint8_t> missing(uint32_t i, std::vector<Ref> refs, const Aabb& voxel) {
        const KdNode& n = tree_.nodes[i];
        std::vector<uint8_t> out(refs.size(), 0);
        if (n.is_leaf()) {
            for (uint32_t k = n.first(); k < n.first() + n.count(); ++k) mark_[tree_.prim_indices[k]] = i;
            for (size_t r = 0; r < refs.size(); ++r) out[r] = mark_[refs[r].prim] != i;
            return out;
        }
        const int axis = n.axis();
        const float pos = n.split();
        Aabb below = voxel, above = voxel;
        below.max[axis] = pos;
        above.min[axis] = pos;
        std::vector<Ref> left, right;
        struct Link {
            uint32_t left = kNone, right = kNone;  // indices of the copies in left / right
            Via via = Via::One;
        };
        std::vector<Link> links(refs.size());
        for (size_t r = 0; r < refs.size(); ++r) {
            const Ref& ref = refs[r];
            const float lo = ref.box.min[axis], hi = ref.box.max[axis];
            Link& l = links[r];
            if (lo == hi && lo == pos) {  // flat in the plane
                l = {uint32_t(left.size()), uint32_t(right.size()), Via::Either};
                left.push_back(ref);
                right.push_back(ref);
            } else if (hi <= pos) {
                l.left = uint32_t(left.size());
                left.push_back(ref);
            } else if (lo >= pos) {
                l.right = uint32_t(right.size());
                right.push_back(ref);
            } else {  // straddles: clipped like the builders' perfect splits
                l.via = Via::Both;
                const Aabb lb = input_.clip(ref.prim, below), rb = input_.clip(ref.prim, above);
                if (!lb.empty()) {
                    l.left = uint32_t(left.size());
                    left.push_back({ref.prim, lb});
                }
                if (!rb.empty()) {
                    l.right = uint32_t(right.size());
                    right.push_back({ref.prim, rb});
                }
            }
        }
        std::vector<Ref>().swap(refs);
        const std::vector<uint8_t> ml = missing(i + 1, std::move(left), below);
        const std::vector<uint8_t> mr = missing(n.above(), std::move(right), above);
        for (size_t r = 0; r < links.size(); ++r) {
            const Link& l = links[r];
            const bool lm = l.left != kNone && ml[l.left], rm = l.right != kNone && mr[l.right];
            out[r] = l.via == Via::Either ? (lm && rm) : (lm || rm);
        }
        return out;
    }

private:
    static constexpr uint32_t kNone = uint32_t(-1);
    const KdTreeData& tree_;
    const KdBuildInput& input_;
    std::vector<uint32_t> mark_;  ///< the leaf that last listed each primitive
};

bool finite_box(const Aabb& b) {
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(b.min[k]) || !std::isfinite(b.max[k])) return false;
    return !b.empty();
}

}  // namespace

void validate_kdtree_coverage(const KdTreeData& tree, const KdBuildInput& input) {
    std::vector<Ref> refs;
    for (uint32_t p = 0; p < input.bounds.size(); ++p) {
        const Aabb& b = input.bounds[p];
        if (!finite_box(b)) continue;  // the builders leave these out: never hit
        for (int a = 0; a < 3; ++a)
            if (b.min[a] < tree.bounds.min[a] || b.max[a] > tree.bounds.max[a])
                throw Error("invalid kD-tree: the root voxel does not contain primitive " + std::to_string(p));
        refs.push_back({p, b});
    }
    if (tree.nodes.empty()) {
        if (!refs.empty()) throw Error("invalid kD-tree: no nodes for " + std::to_string(refs.size()) + " primitives");
        return;
    }
    std::vector<uint32_t> prims(refs.size());
    for (size_t r = 0; r < refs.size(); ++r) prims[r] = refs[r].prim;
    const std::vector<uint8_t> lost = CoverageCheck(tree, input).missing(0, std::move(refs), tree.bounds);
    for (size_t r = 0; r < lost.size(); ++r)
        if (lost[r])
            throw Error("invalid kD-tree: primitive " + std::to_string(prims[r]) +
                        " is missing from a leaf whose cell it reaches");
}

}  // namespace thicket
