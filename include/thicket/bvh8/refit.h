#pragma once
/// Refitting the 8-wide tree after the triangles moved (same topology): the tree keeps its shape,
/// the blocks get the new vertices, every lane's box is recomputed bottom-up (children come
/// after their parents in Tree::nodes), and the figures follow. Baseline code only (no kernel
/// includes this); the caller recomputes the kernels' plane bounds (set_plane_bounds) afterwards.
#include <cstdint>
#include <functional>
#include <string>

#include "thicket/bvh8/blocks.h"
#include "thicket/bvh8/build.h"

namespace thicket::bvh8 {

/// Triangle leaves: re-packs every lane of `blocks` with triangle `id` of `tris`, then refits
/// `tree` and its figures. Any move is taken: a triangle that loses its interior or gains one
/// (a scan's collinear triangle after an affine map) keeps its lane, which the kernels test for
/// degeneracy on every hit (kernel_triangles.inc, plausible_lane), as brute force does.
/// Tris: Triangles<TriangleTest::Moller> or <Watertight> (refit.cpp).
template <class Tris>
void refit_blocks(Tree& tree, Blocks& blocks, const Tris& tris, unsigned threads);

/// Box of the primitives a leaf lane lists: leaf storage [first, first + size).
using LeafBox = std::function<Aabb(uint32_t first, uint32_t size)>;
/// How many primitives a leaf lane tests, for the SAH figures.
using LeafCount = std::function<uint32_t(uint32_t first, uint32_t size)>;

/// Recomputes every lane's box of `tree` (leaf lanes from `leaf_box`, on up to `threads` threads;
/// interior lanes as the union of their child's lanes), tree.bounds as the union of the root's
/// lanes, and tree.sah_cost / embree_sah_cost with `leaf_count` relative to that
/// bounds' area. Any leaf storage (callback ids).
void refit_tree(Tree& tree, const LeafBox& leaf_box, const LeafCount& leaf_count, unsigned threads);

}  // namespace thicket::bvh8
