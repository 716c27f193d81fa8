#pragma once
/// bvh8's closest-point query: the per-ISA traversal (KernelTable::closest_point) decides which
/// leaves to open, nearest box first; the leaves' triangles are tested here, in baseline code, by
/// the point-triangle test brute force uses (Triangles::closest_point), so that every distance is
/// bitwise brute force's.
#include "thicket/bvh8/node.h"
#include "thicket/core/closest_point.h"

namespace thicket::bvh8 {

/// The closest point to p among the triangles of `tree` (its nodes and the blocks its leaves
/// index, degenerate triangles included; null: an empty tree). Equally close triangles go to the
/// lower id, as brute force's scan answers.
NearestPoint closest_point(const KernelTable& kernels, const TraceContext* tree, const Vec3& p);

}  // namespace thicket::bvh8
