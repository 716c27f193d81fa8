#pragma once
/// Refitting a built BVH after its primitives moved: the same tree, every box recomputed.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "thicket/bvh/node.h"
#include "thicket/core/aabb.h"
#include "thicket/util/parallel.h"

namespace thicket {

/// Recomputes every box of `bvh` reachable from the root, leaves from `prim_bounds` (one box per
/// primitive, indexed by id) and each interior node as the union of its children, and the
/// centroid-axis bits of the child-order bytes (the split axis stays: it only orders the visit).
/// A spatial-split tree (builder=sbvh) gets whole-primitive boxes in its leaves, not the clipped
/// ones of its build: larger, so still correct. `prim_bounds` must cover every id the leaves list.
void refit_bvh(BvhData& bvh, std::span<const Aabb> prim_bounds);

/// The box of every primitive of `prims` (bounds(i)), on up to `threads` threads (0: all cores).
template <class Prims>
std::vector<Aabb> refit_boxes(const Prims& prims, unsigned threads) {
    std::vector<Aabb> boxes(prims.size());
    parallel_for(boxes.size(), 4096, threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) boxes[i] = prims.bounds(uint32_t(i));
    });
    return boxes;
}

}  // namespace thicket
