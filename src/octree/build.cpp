// Adaptive octree construction (Glassner 1984), breadth first: one level of cells at a time,
// each cell's references held with the exact bounds of the primitive's part inside the cell, so
// a primitive is clipped again only where it straddles the cell's mid-planes.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "thicket/core/error.h"
#include "thicket/core/ray.h"
#include "thicket/core/sah.h"
#include "thicket/octree/build.h"

namespace thicket {

namespace {

/// A primitive's reference in a cell, with bounds of its part inside the cell: exact (what the
/// clip hook gives), or, when kLoose is set in `prim`, only known to enclose the part.
struct Ref {
    uint32_t prim;
    Aabb part;
};
constexpr uint32_t kLoose = 0x80000000u;

struct Cell {
    uint32_t node, depth;
    Aabb box;
    size_t first, count;  ///< its references in the level's array
};

/// Glassner's cells are cubes: the root is the cube on the scene's lowest corner whose side is the
/// scene's largest extent (widened where rounding would leave the scene outside). Cells of a flat
/// scene are then never flat themselves, only the scene inside them.
Aabb root_cube(const Aabb& scene) {
    const float side = max_component(scene.extent());
    Aabb root{scene.min, scene.min};
    for (int a = 0; a < 3; ++a) root.max[a] = std::max(scene.min[a] + side, scene.max[a]);
    return root;
}

/// Most nodes a tree may have (node indices are 32-bit, kInner reserved).
constexpr size_t kMaxNodes = size_t(1) << 31;

/// Whether [lo, hi] reaches beyond `plane` on both sides by more than the clip hook's outward
/// rounding (two ulps), so that the part really has points on either side.
bool straddles(float lo, float hi, float plane) {
    const float below = std::nextafter(std::nextafter(plane, -kInfinity), -kInfinity);
    const float above = std::nextafter(std::nextafter(plane, kInfinity), kInfinity);
    return lo < below && hi > above;
}

class Distributor {
public:
    explicit Distributor(const OctreeClip& clip) : clip_(clip) {}

    /// Sorts the cell's references into its eight children, clipping as little as exactness
    /// allows. A part inside one child goes there unchanged. A loose part that crosses a
    /// mid-plane is first made exact by one clip against the cell; then place() splits it.
    void run(std::span<const Ref> refs, const Aabb& box) {
        for (auto& child : children) child.clear();
        for (int a = 0; a < 3; ++a) mid_[a] = octree_mid(box.min[a], box.max[a]);
        for (Ref r : refs) {
            if (crossed(r.part, 7) == 0) {
                children[side_bits(r.part, 7)].push_back(r);
                continue;
            }
            const uint32_t prim = r.prim & ~kLoose;
            const Aabb part = r.prim & kLoose ? clip_(prim, box) : r.part;
            if (!part.empty()) place(prim, part, box, 7, 0);
        }
    }

    std::array<std::vector<Ref>, 8> children;

private:
    /// Mask of the axes (among `axes`) on which the part reaches both halves of the cell.
    int crossed(const Aabb& part, int axes) const {
        int mask = 0;
        for (int a = 0; a < 3; ++a) mask |= int(part.min[a] <= mid_[a] && part.max[a] >= mid_[a]) << a;
        return mask & axes;
    }

    /// Child index bits, on `axes`, of a part that crosses none of their mid-planes.
    int side_bits(const Aabb& part, int axes) const {
        int c = 0;
        for (int a = 0; a < 3; ++a) c |= int(part.min[a] > mid_[a]) << a;
        return c & axes;
    }

    /// Places a primitive whose exact part in `region` (the cell, or the cell halved on the
    /// axes not in `axes`, on the sides given by `bits`) crosses mid-planes. Crossing one plane by more than rounding, it goes
    /// to both sides unclipped, marked loose: its exact box's extremes are points of the part,
    /// one on each side, and on the other axes all of it lies in one half. Otherwise it is
    /// clipped to both halves of the region on one crossed axis, and each half placed in turn
    /// (a quadrant of a part crossing two planes can be empty).
    void place(uint32_t prim, const Aabb& part, const Aabb& region, int axes, int bits) {
        const int mask = crossed(part, axes);
        if (mask == 0) {
            children[bits | side_bits(part, axes)].push_back({prim, part});
            return;
        }
        const int axis = mask & 1 ? 0 : (mask & 2 ? 1 : 2);
        const int others = axes & ~(1 << axis);
        if (mask == (1 << axis) && straddles(part.min[axis], part.max[axis], mid_[axis])) {
            for (const int upper : {0, 1}) {
                Aabb half = part;
                (upper ? half.min : half.max)[axis] = mid_[axis];
                children[bits | side_bits(part, others) | (upper << axis)].push_back({prim | kLoose, half});
            }
            return;
        }
        for (const int upper : {0, 1}) {
            Aabb half = region;
            (upper ? half.min : half.max)[axis] = mid_[axis];
            const Aabb sub = clip_(prim, half);
            if (!sub.empty()) place(prim, sub, half, others, bits | (upper << axis));
        }
    }

    const OctreeClip& clip_;
    Vec3 mid_;
};

}  // namespace

OctreeData build_octree(std::span<const Aabb> bounds, const OctreeClip& clip, const OctreeBuildOptions& options) {
    if (options.leaf_size < 1)
        throw Error("build_octree: leaf-size=" + std::to_string(options.leaf_size) + " must be at least 1");
    if (options.max_depth < 0 || options.max_depth > int(kOctreeMaxDepth))
        throw Error("build_octree: max-depth=" + std::to_string(options.max_depth) + " must be in [0, " +
                    std::to_string(kOctreeMaxDepth) + "]");
    if (bounds.size() >= kLoose) throw Error("build_octree: more than 2^31 primitives");
    OctreeData tree;
    Aabb scene;
    for (const Aabb& b : bounds) scene.grow(b);
    if (scene.empty()) return tree;
    tree.root = root_cube(scene);

    std::vector<Ref> refs;
    refs.reserve(bounds.size());
    for (uint32_t i = 0; i < bounds.size(); ++i)
        if (!bounds[i].empty()) refs.push_back({i, bounds[i]});  // the root holds all of it
    std::vector<Cell> level{{0, 0, tree.root, 0, refs.size()}};
    tree.nodes.push_back({});

    // References the finished tree would hold if no further cell were split.
    size_t committed = refs.size();
    const size_t budget = kOctreeReferenceBudget * bounds.size() + 4096;
    Distributor split(clip);
    while (!level.empty()) {
        std::vector<Cell> next;
        std::vector<Ref> next_refs;
        // Crowded cells first: if the reference budget runs out during this level, it has been
        // spent where splitting separates most, not on whichever octants come first.
        std::stable_sort(level.begin(), level.end(), [](const Cell& a, const Cell& b) { return a.count > b.count; });
        for (const Cell& cell : level) {
            const std::span<const Ref> mine(refs.data() + cell.first, cell.count);
            bool leaf = cell.count <= size_t(options.leaf_size) || cell.depth >= uint32_t(options.max_depth) ||
                        committed >= budget || tree.nodes.size() + 8 > kMaxNodes;
            size_t total = 0;
            if (!leaf) {
                split.run(mine, cell.box);
                size_t non_empty = 0, full = 0;
                for (const auto& child : split.children) {
                    total += child.size();
                    non_empty += !child.empty();
                    full += child.size() == cell.count;
                }
                // Nothing is separated when every non-empty child would hold the whole cell
                // (overlapping or coincident geometry); one non-empty child still sheds space.
                leaf = (non_empty >= 2 && full == non_empty) || committed - cell.count + total > budget;
            }
            if (leaf) {
                tree.nodes[cell.node] = {uint32_t(tree.refs.size()), uint32_t(cell.count)};
                for (const Ref& r : mine) tree.refs.push_back(r.prim & ~kLoose);
                continue;
            }
            committed = committed - cell.count + total;
            const auto first = uint32_t(tree.nodes.size());
            tree.nodes.resize(tree.nodes.size() + 8);
            tree.nodes[cell.node] = {first, OctreeNode::kInner};
            for (int c = 0; c < 8; ++c) {
                next.push_back({first + c, cell.depth + 1, octree_child_box(cell.box, c), next_refs.size(),
                                split.children[c].size()});
                next_refs.insert(next_refs.end(), split.children[c].begin(), split.children[c].end());
            }
        }
        level.swap(next);
        refs.swap(next_refs);
    }
    if (tree.refs.size() >= OctreeNode::kInner) throw Error("build_octree: more than 2^32 references");
    return tree;
}

OctreeFigures octree_figures(const OctreeData& tree) {
    OctreeFigures f = walk_tree(!tree.nodes.empty(), tree.root,
                                [&](const TreeWalkItem& item, double, auto push) -> std::optional<size_t> {
                                    const OctreeNode& node = tree.nodes[item.node];
                                    if (node.is_leaf()) return node.count;
                                    for (int c = 7; c >= 0; --c)
                                        push({node.index + uint32_t(c), item.depth + 1,
                                              octree_child_box(item.box, c)});
                                    return std::nullopt;
                                });
    if (!tree.nodes.empty()) f.references = tree.refs.size();
    return f;
}

}  // namespace thicket
