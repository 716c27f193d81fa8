// What octree traversal relies on beyond the tree's structure: every leaf lists every primitive
// whose part reaches its cell. A well-formed tree can still leave one out (a changed id or leaf
// range, a split where the builder made a leaf); a ray through that cell would then miss it.
// The proof replays the builder's distribution (distribute.h, the same code) over the stored
// tree, level by level from the builder's root cube, and looks each primitive up in the leaves it
// reaches. Extra entries in a leaf only cost time. The builder never holds more than its
// reference budget in one level; a tree that would make the replay do so is refused, which
// bounds the proof's time and memory on any file.
#include <string>
#include <vector>

#include "distribute.h"
#include "thicket/core/error.h"
#include "thicket/octree/build.h"

namespace thicket {

namespace {

bool same_box(const Aabb& a, const Aabb& b) {
    for (int k = 0; k < 3; ++k)
        if (!(a.min[k] == b.min[k] && a.max[k] == b.max[k])) return false;
    return true;
}

}  // namespace

void validate_octree_coverage(const OctreeData& tree, std::span<const Aabb> bounds, const OctreeClip& clip) {
    using octree_detail::kLoose;
    using octree_detail::Ref;
    Aabb scene;
    for (const Aabb& b : bounds) scene.grow(b);
    if (scene.empty()) {
        if (!tree.nodes.empty()) throw Error("invalid octree: nodes over primitives that have no bounds");
        return;
    }
    if (tree.nodes.empty())
        throw Error("invalid octree: no nodes for " + std::to_string(bounds.size()) + " primitives");
    if (!same_box(tree.root, octree_root_cube(scene)))
        throw Error("invalid octree: the root cell is not the cube the builder puts around the scene");

    struct Cell {
        uint32_t node;
        Aabb box;
        size_t first, count;  ///< its references in the level's array
    };
    std::vector<Ref> refs;
    for (uint32_t i = 0; i < bounds.size(); ++i)
        if (!bounds[i].empty()) refs.push_back({i, bounds[i]});
    std::vector<Cell> level{{0, tree.root, 0, refs.size()}};
    constexpr uint32_t kNone = ~0u;  // never a node index (kOctreeMaxNodes)
    std::vector<uint32_t> listed_by(bounds.size(), kNone);
    const size_t budget = octree_reference_budget(bounds.size());
    octree_detail::Distributor split(clip);
    while (!level.empty()) {
        std::vector<Cell> next;
        std::vector<Ref> next_refs;
        for (const Cell& cell : level) {
            const OctreeNode& node = tree.nodes[cell.node];
            const std::span<const Ref> mine(refs.data() + cell.first, cell.count);
            if (node.is_leaf()) {
                for (uint32_t k = node.index; k < node.index + node.count; ++k) listed_by[tree.refs[k]] = cell.node;
                for (const Ref& r : mine)
                    if (listed_by[r.prim & ~kLoose] != cell.node)
                        throw Error("invalid octree: leaf " + std::to_string(cell.node) + " does not list primitive " +
                                    std::to_string(r.prim & ~kLoose) + ", whose part reaches its cell");
                continue;
            }
            split.run(mine, cell.box);
            for (int c = 0; c < 8; ++c) {
                next.push_back({node.index + uint32_t(c), octree_child_box(cell.box, c), next_refs.size(),
                                split.children[c].size()});
                next_refs.insert(next_refs.end(), split.children[c].begin(), split.children[c].end());
            }
            if (next_refs.size() > budget)
                throw Error("invalid octree: its cells would hold more than the builder's budget of " +
                            std::to_string(budget) + " references in one level");
        }
        level.swap(next);
        refs.swap(next_refs);
    }
}

}  // namespace thicket
