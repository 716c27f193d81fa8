// bvh8 payload: lengths, then the arrays as they are in memory (nodes and blocks are plain,
// relocatable data), then the build's figures. Reading bounds every length by the scene's
// primitive count before allocating; the structure, the boxes and the leaves are then proved.
#include "thicket/bvh8/bvh8_io.h"

#include <algorithm>
#include <bit>
#include <string>
#include <utility>
#include <vector>

#include "bvh/coverage.h"
#include "thicket/core/error.h"
#include "thicket/core/ray.h"
#include "thicket/prims/triangles.h"
#include "thicket/util/binary_io.h"

namespace thicket::bvh8 {

namespace {

/// A tree over n primitives has at most n leaves and so fewer than n nodes of two or more
/// children, plus a root; spatial splits may repeat a primitive, so blocks and ids are bounded
/// by a generous multiple of n rather than by n itself.
constexpr size_t kMaxReferencesPerPrimitive = 4;

}  // namespace

void write_tree(std::ostream& out, const Tree& tree, const Blocks& blocks, const std::vector<uint32_t>& ids) {
    write_value(out, uint64_t(tree.nodes.size()));
    write_value(out, uint64_t(blocks.size()));
    write_value(out, uint64_t(ids.size()));
    write_array(out, tree.nodes.data(), tree.nodes.size());
    write_array(out, blocks.data(), blocks.size());
    write_array(out, ids.data(), ids.size());
    write_value(out, tree.sah_cost);
    write_value(out, tree.embree_sah_cost);
}

SavedTree read_tree(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "bvh8");
    uint64_t nodes = 0, blocks = 0, ids = 0;
    reader.value(nodes, "node count");
    reader.value(blocks, "block count");
    reader.value(ids, "id count");
    if (blocks && ids) throw Error("bvh8 payload holds both triangle blocks and primitive ids");
    if (nodes == 0 && (blocks || ids)) throw Error("bvh8 payload has leaves but no nodes");
    SavedTree saved;
    const uint64_t references = kMaxReferencesPerPrimitive * uint64_t(primitive_count);
    reader.array(saved.tree.nodes, nodes, uint64_t(primitive_count) + 1, "nodes");
    reader.array(saved.blocks, blocks, references, "4-triangle blocks");
    reader.array(saved.ids, ids, references, "primitive ids");
    reader.value(saved.tree.sah_cost, "SAH cost");
    reader.value(saved.tree.embree_sah_cost, "Embree SAH cost");
    reader.end();
    validate_tree(saved.tree, blocks ? blocks : ids);
    return saved;
}

/// Which nodes traversal reaches: children lie after their parent (validate_tree), so a node is
/// reachable iff a reachable node before it points to it, and one forward pass marks them all.
static std::vector<bool> reachable_nodes(const Tree& tree) {
    std::vector<bool> reachable(tree.nodes.size(), false);
    if (tree.nodes.empty()) return reachable;
    reachable[0] = true;
    for (size_t n = 0; n < tree.nodes.size(); ++n) {
        if (!reachable[n]) continue;
        const Node& node = tree.nodes[n];
        for (int lane = 0; lane < kWidth; ++lane)
            if ((node.valid >> lane & 1) && node.leaf_size[lane] == 0) reachable[node.child[lane]] = true;
    }
    return reachable;
}

void for_each_leaf(const Tree& tree, const std::function<void(uint32_t first, uint32_t size)>& visit) {
    const std::vector<bool> reachable = reachable_nodes(tree);
    for (size_t n = 0; n < tree.nodes.size(); ++n) {
        if (!reachable[n]) continue;
        const Node& node = tree.nodes[n];
        for (int lane = 0; lane < kWidth; ++lane)
            if ((node.valid >> lane & 1) && node.leaf_size[lane] != 0) visit(node.child[lane], node.leaf_size[lane]);
    }
}

void check_boxes(Tree& tree, const LeafPrimitives& leaf_primitives, std::span<const Aabb> prim_bounds,
                 const ClipFunction& clip) {
    tree.leaves = 0;
    tree.max_depth = 0;
    if (tree.nodes.empty()) return;
    const std::vector<bool> reachable = reachable_nodes(tree);
    auto box_of = [](const Node& node, int lane) {
        Aabb box;
        for (int a = 0; a < 3; ++a) box.min[a] = node.box[a][0][lane], box.max[a] = node.box[a][1][lane];
        return box;
    };
    auto encloses = [](const Aabb& box, const Aabb& below) {
        for (int a = 0; a < 3; ++a)
            if (!(box.min[a] <= below.min[a] && below.max[a] <= box.max[a])) return false;
        return true;
    };
    // Backwards, so that a child node's content box is known before its parent's lane is checked;
    // every (primitive, leaf box) listing is kept for the per-primitive proof after.
    std::vector<Aabb> content(tree.nodes.size());
    std::vector<size_t> height(tree.nodes.size(), 1);
    std::vector<std::pair<uint32_t, Aabb>> listings;
    for (size_t n = tree.nodes.size(); n-- > 0;) {
        if (!reachable[n]) continue;
        const Node& node = tree.nodes[n];
        for (int lane = 0; lane < kWidth; ++lane) {
            if (!(node.valid >> lane & 1)) continue;
            const Aabb box = box_of(node, lane);
            if (node.leaf_size[lane] == 0) {
                const Aabb& below = content[node.child[lane]];
                if (!below.empty() && !encloses(box, below))
                    throw Error("bvh8: node " + std::to_string(n) + " lane " + std::to_string(lane) +
                                ": its box does not enclose its child node's");
                height[n] = std::max(height[n], height[node.child[lane]] + 1);
            } else {
                leaf_primitives(node.child[lane], node.leaf_size[lane], [&](uint32_t p) { listings.push_back({p, box}); });
                height[n] = std::max<size_t>(height[n], 2);  // the leaves' level counts (Tree::max_depth)
                ++tree.leaves;
            }
            content[n].grow(box);
        }
    }
    tree.max_depth = height[0];
    std::stable_sort(listings.begin(), listings.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    CoverageProof proof(prim_bounds, clip);
    std::vector<Aabb> boxes;
    for (size_t i = 0; i < listings.size();) {
        const uint32_t p = listings[i].first;
        if (p >= prim_bounds.size()) throw Error("bvh8: a leaf lists primitive " + std::to_string(p));
        size_t end = i;
        while (end < listings.size() && listings[end].first == p) ++end;
        if (end - i == 1) {  // every primitive of an object-partition tree
            if (!encloses(listings[i].second, prim_bounds[p]))
                throw Error("bvh8: the box of the leaf holding primitive " + std::to_string(p) +
                            " does not enclose it");
        } else {
            boxes.clear();
            for (size_t k = i; k < end; ++k) boxes.push_back(listings[k].second);
            proof.check(p, boxes);
        }
        i = end;
    }
}

/// A loaded block: each lane either triangle `id` of `tris` bit for bit, or
/// kNoPrim with all-zero vertices (never hit). Marks the triangles seen; counts the lanes filled.
template <class Tris>
static void check_block(const Blocks& blocks, uint32_t index, const Tris& tris, std::vector<bool>& seen,
                        size_t& lanes) {
    const Tri4& b = blocks[index];
    for (int lane = 0; lane < 4; ++lane) {
        const std::string where = "bvh8: block " + std::to_string(index) + " lane " + std::to_string(lane);
        if (b.id[lane] == kNoPrim) {
            for (int vertex = 0; vertex < 3; ++vertex)
                for (int a = 0; a < 3; ++a)
                    if (b.v[vertex][a][lane] != 0.0f) throw Error(where + ": an empty lane with a vertex");
            continue;
        }
        if (b.id[lane] >= tris.size())
            throw Error(where + " names triangle " + std::to_string(b.id[lane]) + " of " + std::to_string(tris.size()));
        const auto v = tris.triangle(b.id[lane]);
        for (int vertex = 0; vertex < 3; ++vertex)
            for (int a = 0; a < 3; ++a)
                if (std::bit_cast<uint32_t>(b.v[vertex][a][lane]) != std::bit_cast<uint32_t>(v[size_t(vertex)][a]))
                    throw Error(where + ": triangle " + std::to_string(b.id[lane]) + " differs from the scene's");
        seen[b.id[lane]] = true;
        ++lanes;
    }
}

template <class Tris>
size_t prove_blocks(Tree& tree, const Blocks& blocks, const std::vector<uint32_t>& ids, const Tris& tris,
                          std::span<const Aabb> bounds, const ClipFunction& clip) {
    if (!ids.empty()) throw Error("bvh8: a triangle scene's payload lists primitive ids, not blocks");
    size_t lanes = 0;
    std::vector<bool> seen(tris.size(), false);
    for_each_leaf(tree, [&](uint32_t first, uint32_t size) {
        for (uint32_t b = first; b < first + size; ++b) check_block(blocks, b, tris, seen, lanes);
    });
    check_boxes(
        tree,
        [&](uint32_t first, uint32_t size, const std::function<void(uint32_t)>& id) {
            for (uint32_t b = first; b < first + size; ++b)
                for (uint32_t lane_id : blocks[b].id)
                    if (lane_id != kNoPrim) id(lane_id);
        },
        bounds, clip);
    for (uint32_t i = 0; i < tris.size(); ++i) {
        if (seen[i]) continue;
        const auto v = tris.triangle(i);
        if (Tris::degenerate({v[0], v[1], v[2]}))
            throw Error("bvh8: degenerate triangle " + std::to_string(i) +
                        " is in no leaf: the file was saved by a thicket whose bvh8 left degenerate triangles out "
                        "of its blocks (before 2026-12-07); build and save the structure again");
        throw Error("bvh8: triangle " + std::to_string(i) + " is in no leaf");
    }
    return lanes;
}

template size_t prove_blocks(Tree&, const Blocks&, const std::vector<uint32_t>&,
                                   const Triangles<TriangleTest::Moller>&, std::span<const Aabb>, const ClipFunction&);
template size_t prove_blocks(Tree&, const Blocks&, const std::vector<uint32_t>&,
                                   const Triangles<TriangleTest::Watertight>&, std::span<const Aabb>,
                                   const ClipFunction&);

void prove_ids(Tree& tree, const Blocks& blocks, const std::vector<uint32_t>& ids, std::span<const Aabb> bounds,
               const ClipFunction& clip) {
    if (!blocks.empty()) throw Error("bvh8: payload holds triangle blocks for a scene that is not only triangles");
    const size_t primitives = bounds.size();
    std::vector<bool> seen(primitives, false);
    for_each_leaf(tree, [&](uint32_t first, uint32_t size) {
        for (uint32_t k = first; k < first + size; ++k) {
            if (ids[k] >= primitives)
                throw Error("bvh8: leaf entry " + std::to_string(k) + " names primitive " + std::to_string(ids[k]) +
                            " of " + std::to_string(primitives));
            seen[ids[k]] = true;
        }
    });
    check_boxes(
        tree,
        [&](uint32_t first, uint32_t size, const std::function<void(uint32_t)>& id) {
            for (uint32_t k = first; k < first + size; ++k) id(ids[k]);
        },
        bounds, clip);
    for (uint32_t i = 0; i < primitives; ++i)
        if (!seen[i]) throw Error("bvh8: primitive " + std::to_string(i) + " is in no leaf");
}

}  // namespace thicket::bvh8
