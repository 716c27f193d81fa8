#pragma once
/// The degenerate-triangle ("sliver") tree. Degenerate triangles have no interior for rays, so
/// the blocks rays see leave them out; but their points are on the surface and brute force
/// answers them as closest points. They get an 8-wide tree of their own, usually empty or tiny,
/// which only the closest-point query searches.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "thicket/bvh/build.h"
#include "thicket/bvh8/blocks.h"
#include "thicket/bvh8/build.h"

namespace thicket::bvh8 {

/// The sliver tree: nodes and the blocks its leaves index (every lane a degenerate triangle).
struct SliverTree {
    Tree tree;
    Blocks blocks;
};

/// How many triangles of `tris` are degenerate (Triangles::degenerate): the blocks drop them.
template <class Tris>
size_t count_degenerate(const Tris& tris);

/// The tree over the triangles `slivers` lists (each once however often it is listed: spatial
/// splits may list a sliver in several leaves), built as the main tree with `binary` and
/// `merge_below` but always by object partition (builder=sbvh falls back to binned SAH).
/// Tris: Triangles<TriangleTest::Moller> or Triangles<TriangleTest::Watertight> (slivers.cpp).
template <class Tris>
SliverTree build_sliver_tree(const Tris& tris, std::vector<uint32_t> slivers, const BvhBuildOptions& binary,
                             uint32_t merge_below);

}  // namespace thicket::bvh8
