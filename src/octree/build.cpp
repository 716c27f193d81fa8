// Adaptive octree construction (Glassner 1984), breadth first: one level of cells at a time,
// each cell's references held with the exact bounds of the primitive's part inside the cell, so
// a primitive is clipped again only where it straddles the cell's mid-planes.
#include <array>
#include <string>

#include "thicket/accel/accel.h"
#include "thicket/core/error.h"
#include "thicket/octree/build.h"

namespace thicket {

namespace {

/// A primitive's reference in a cell, with the bounds of its part inside the cell.
struct Ref {
    uint32_t prim;
    Aabb part;
};

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

class Distributor {
public:
    explicit Distributor(const OctreeClip& clip) : clip_(clip) {}

    /// Sorts the cell's references into its eight children: a reference whose part lies in one
    /// child keeps its part; one straddling mid-planes is clipped exactly against each child it
    /// may touch and goes to those where something remains.
    void run(std::span<const Ref> refs, const Aabb& box) {
        for (auto& child : children) child.clear();
        Vec3 mid;
        for (int a = 0; a < 3; ++a) mid[a] = octree_mid(box.min[a], box.max[a]);
        for (const Ref& r : refs) {
            int lower = 0, upper = 0;  // axes on which the part reaches the lower / upper half
            for (int a = 0; a < 3; ++a) {
                lower |= (r.part.min[a] <= mid[a]) << a;
                upper |= (r.part.max[a] >= mid[a]) << a;
            }
            if ((lower & upper) == 0) {
                children[upper].push_back(r);  // in one child: the part is unchanged
                continue;
            }
            for (int c = 0; c < 8; ++c) {
                // Child c needs the part on its side of every axis.
                if ((c & ~upper) != 0 || (~c & ~lower & 7) != 0) continue;
                const Aabb part = clip_(r.prim, octree_child_box(box, c));
                if (!part.empty()) children[c].push_back({r.prim, part});
            }
        }
    }

    std::array<std::vector<Ref>, 8> children;

private:
    const OctreeClip& clip_;
};

}  // namespace

OctreeData build_octree(std::span<const Aabb> bounds, const OctreeClip& clip, const OctreeBuildOptions& options) {
    if (options.leaf_size < 1)
        throw Error("build_octree: leaf-size=" + std::to_string(options.leaf_size) + " must be at least 1");
    if (options.max_depth < 0 || options.max_depth > int(kOctreeMaxDepth))
        throw Error("build_octree: max-depth=" + std::to_string(options.max_depth) + " must be in [0, " +
                    std::to_string(kOctreeMaxDepth) + "]");
    if (bounds.size() > 0xFFFFFFF0u) throw Error("build_octree: more than 2^32 primitives");
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
        for (const Cell& cell : level) {
            const std::span<const Ref> mine(refs.data() + cell.first, cell.count);
            bool leaf = cell.count <= size_t(options.leaf_size) || cell.depth >= uint32_t(options.max_depth) ||
                        tree.nodes.size() + 8 > kMaxNodes;
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
                for (const Ref& r : mine) tree.refs.push_back(r.prim);
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
    OctreeFigures f;
    if (tree.nodes.empty()) return f;
    f.references = tree.refs.size();
    const float root_area = tree.root.half_area();
    struct Item {
        uint32_t node;
        size_t depth;
        Aabb box;
    };
    std::vector<Item> stack{{0, 0, tree.root}};
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        const OctreeNode& node = tree.nodes[item.node];
        // A point-sized root (one degenerate primitive) weighs every cell equally.
        const double rel = root_area > 0.0f ? double(item.box.half_area()) / root_area : 1.0;
        ++f.nodes;
        f.max_depth = std::max(f.max_depth, item.depth);
        if (node.is_leaf()) {
            ++f.leaves;
            f.empty_leaves += node.count == 0;
            f.max_leaf_size = std::max<size_t>(f.max_leaf_size, node.count);
            f.sah_cost += rel * kSahIntersectionCost * node.count;
            continue;
        }
        f.sah_cost += rel * kSahTraversalCost;
        for (int c = 7; c >= 0; --c) stack.push_back({node.index + uint32_t(c), item.depth + 1, octree_child_box(item.box, c)});
    }
    return f;
}

}  // namespace thicket
