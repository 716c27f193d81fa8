#pragma once
/// What a bvh8 reports (`thicket info`, AccelStats): the tree's figures, its memory and, for
/// triangle scenes, how full the 4-triangle blocks are.
#include <cstddef>
#include <cstdint>

#include "thicket/accel/accel.h"
#include "thicket/bvh8/build.h"

namespace thicket::bvh8 {

/// The figures stats() reports, as plain data.
struct StatsFigures {
    const Tree* tree = nullptr;  ///< the tree rays traverse (its figures; nodes may be compressed away)
    size_t node_count = 0;       ///< its 8-wide nodes
    size_t node_bytes = 0;       ///< bytes per node: sizeof(Node), or sizeof(QNode) when compressed
    const char* isa = "";        ///< the kernels' level
    size_t primitives = 0;       ///< in the scene
    size_t references = 0;       ///< entries of the binary tree's leaves
    size_t ids = 0;              ///< primitive ids stored (leaves of shapes)
    size_t primitive_bytes = 0;  ///< the blocks, or the primitive set the leaves' ids index
    bool blocks = false;         ///< the leaves are 4-triangle blocks: the three figures below apply
    size_t block_count = 0;      ///< blocks rays see
    size_t lanes = 0;            ///< their lanes filled
    size_t degenerate = 0;       ///< lanes holding a degenerate triangle (kept, never hit)
    uint64_t packet_rays = 0;    ///< rays the packet kernels have answered so far
};

/// Fills `s` (base_stats() already in it) from the figures.
void fill_stats(AccelStats& s, const StatsFigures& f);

}  // namespace thicket::bvh8
