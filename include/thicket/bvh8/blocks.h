#pragma once
/// 4-triangle blocks: packing a leaf's triangles into the Tri4 lanes the kernels read (node.h
/// holds the layout itself). Baseline code only: no kernel file includes this header.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "thicket/bvh8/build.h"
#include "thicket/bvh8/node.h"
#include "thicket/core/aligned.h"

namespace thicket::bvh8 {

/// A tree's leaf storage for triangle scenes: the structure's only copy of the triangles.
using Blocks = AlignedVector<Tri4, 64>;

/// How one tree's leaves are packed, and what the packing counted so far.
struct BlockPacking {
    /// Spatial splits (builder=sbvh) listed some triangle in several binary leaves: a merged leaf
    /// (leaf-merge) may then hold both parts of one, and one lane is enough.
    bool may_repeat = false;
    size_t lanes = 0;  ///< lanes filled
};

/// Appends triangles prims[0..count) of `tris` to `blocks`, four to a block in that order, unused
/// lanes kNoPrim with all-zero vertices; returns where they went. Degenerate triangles are kept:
/// the kernels never report their hits (as Triangles::plausible), closest points reach them, and
/// a refit may give them an interior again.
/// Tris: Triangles<TriangleTest::Moller> or Triangles<TriangleTest::Watertight> (blocks.cpp).
template <class Tris>
LeafPlacement pack_blocks(Blocks& blocks, const Tris& tris, const uint32_t* prims, uint32_t count,
                          BlockPacking& packing);

/// How many filled lanes of `blocks` hold a degenerate triangle (Triangles::degenerate): lanes
/// rays never hit (stats' "degenerate lanes"). The test is the same for both triangle sets.
size_t degenerate_lanes(const Blocks& blocks);

}  // namespace thicket::bvh8
