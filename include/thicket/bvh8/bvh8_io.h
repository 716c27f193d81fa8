#pragma once
/// Saving and loading an 8-wide tree: the node array, the leaf storage (4-triangle blocks or
/// primitive ids) and the build's figures, as they are in memory, each preceded by its length.
/// Loading proves what the kernels rely on before anything is traced: the tree's structure
/// (validate_tree), that every box encloses what lies below it, and that the leaves hold the
/// scene's own primitives (prove_blocks, prove_ids: Bvh8's loading constructor calls one).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <istream>
#include <ostream>
#include <span>
#include <vector>

#include "thicket/bvh/build.h"
#include "thicket/bvh8/blocks.h"
#include "thicket/bvh8/build.h"

namespace thicket::bvh8 {

/// What a saved bvh8 holds besides its primitives' identity.
struct SavedTree {
    Tree tree;
    Blocks blocks;                   ///< triangle sets
    std::vector<uint32_t> ids;       ///< other primitive sets
};

/// Writes the payload; `blocks` or `ids` is empty (whichever the leaf kind does not use).
void write_tree(std::ostream& out, const Tree& tree, const Blocks& blocks, const std::vector<uint32_t>& ids);

/// Reads a payload written by write_tree for a scene of `primitive_count` primitives: every
/// length checked against it before allocating, then validate_tree. Throws Error naming what is
/// wrong. The caller then proves the leaves and the boxes (prove_blocks or prove_ids).
SavedTree read_tree(std::istream& in, size_t primitive_count);

/// Calls `id(p)` for every primitive id a leaf lane (first, size as stored in the node) lists.
using LeafPrimitives = std::function<void(uint32_t first, uint32_t size, const std::function<void(uint32_t)>& id)>;

/// Proves, over the nodes reachable from the root, that every valid lane's box encloses what
/// lies below it: a child node's valid lanes' boxes; a primitive that one leaf lists, its bounds
/// (`prim_bounds`); a primitive that spatial splits cut into several leaves, every part of it
/// in one of their boxes (the BVH's CoverageProof, with `clip`). Recomputes tree.leaves and
/// tree.max_depth. Throws Error naming the first lane or primitive that is not enclosed.
void check_boxes(Tree& tree, const LeafPrimitives& leaf_primitives, std::span<const Aabb> prim_bounds,
                 const ClipFunction& clip);

/// Calls `visit(first, size)` for every leaf lane reachable from the root.
void for_each_leaf(const Tree& tree, const std::function<void(uint32_t first, uint32_t size)>& visit);

/// Proves a loaded triangle tree against the scene's triangles `tris` (bounds: theirs, clip:
/// their clipped bounds): the payload holds blocks, not ids; every block lane of a reachable leaf
/// is either a triangle of the scene bit for bit (degenerate ones included: the blocks keep them)
/// or kNoPrim with all-zero vertices; the boxes enclose them (check_boxes); every triangle is in
/// a leaf. Returns the lanes filled (a triangle once per leaf listing it). Throws Error naming the
/// first block, lane or triangle that is wrong; a file whose blocks leave degenerate triangles
/// out (saved before 2026-12-07, when the blocks dropped them) is told to be built again.
/// Tris: Triangles<TriangleTest::Moller> or Triangles<TriangleTest::Watertight> (bvh8_io.cpp).
template <class Tris>
size_t prove_blocks(Tree& tree, const Blocks& blocks, const std::vector<uint32_t>& ids, const Tris& tris,
                    std::span<const Aabb> bounds, const ClipFunction& clip);

/// Proves a loaded tree of primitive-id leaves over `bounds.size()` primitives: the payload holds
/// ids, not blocks; every id of a reachable leaf names a primitive; the boxes enclose them
/// (check_boxes); every primitive is in a leaf. Throws Error naming the first that is wrong.
void prove_ids(Tree& tree, const Blocks& blocks, const std::vector<uint32_t>& ids, std::span<const Aabb> bounds,
               const ClipFunction& clip);

}  // namespace thicket::bvh8
