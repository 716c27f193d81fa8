#pragma once
/// bvh8's closest-point query: the per-ISA traversal (KernelTable::closest_point) decides which
/// leaves to open, nearest box first; the leaves' triangles are tested here, in baseline code, by
/// the point-triangle test brute force uses (Triangles::closest_point), so that every distance is
/// bitwise brute force's.
#include <initializer_list>

#include "thicket/bvh8/node.h"
#include "thicket/core/closest_point.h"

namespace thicket::bvh8 {

/// The closest point to p among the triangles of `trees` (each a tree's nodes and the blocks its
/// leaves index; a null entry is an empty tree), searched in order, each pruned by the best point
/// of those before. Equally close triangles go to the lower id, as brute force's scan answers.
NearestPoint closest_point(const KernelTable& kernels, std::initializer_list<const TraceContext*> trees, const Vec3& p);

}  // namespace thicket::bvh8
