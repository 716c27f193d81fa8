// Adaptive octree construction (Glassner 1984), breadth first: one level of cells at a time,
// each cell's references held with the exact bounds of the primitive's part inside the cell, so
// a primitive is clipped again only where it straddles the cell's mid-planes.
#include <algorithm>
#include <string>

#include "distribute.h"
#include "thicket/core/error.h"
#include "thicket/core/sah.h"
#include "thicket/octree/build.h"

namespace thicket {

namespace {

using octree_detail::Distributor;
using octree_detail::kLoose;
using octree_detail::Ref;

struct Cell {
    uint32_t node, depth;
    Aabb box;
    size_t first, count;  ///< its references in the level's array
};

}  // namespace

// Widened where rounding would leave the scene outside. Cells of a flat scene are then never
// flat themselves, only the scene inside them.
Aabb octree_root_cube(const Aabb& scene) {
    const float side = max_component(scene.extent());
    Aabb root{scene.min, scene.min};
    for (int a = 0; a < 3; ++a) root.max[a] = std::max(scene.min[a] + side, scene.max[a]);
    return root;
}

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
    tree.root = octree_root_cube(scene);

    std::vector<Ref> refs;
    refs.reserve(bounds.size());
    for (uint32_t i = 0; i < bounds.size(); ++i)
        if (!bounds[i].empty()) refs.push_back({i, bounds[i]});  // the root holds all of it
    std::vector<Cell> level{{0, 0, tree.root, 0, refs.size()}};
    tree.nodes.push_back({});

    // References the finished tree would hold if no further cell were split.
    size_t committed = refs.size();
    const size_t budget = octree_reference_budget(bounds.size());
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
                        committed >= budget || tree.nodes.size() + 8 > kOctreeMaxNodes;
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
