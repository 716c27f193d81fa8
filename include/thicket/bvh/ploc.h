#pragma once
/// The PLOC builder's entry point and its work counts (builder=ploc goes through build_bvh).
#include <cstdint>

#include "thicket/bvh/build.h"

namespace thicket {

/// What a PLOC build did, counted rather than timed: the work is O(radius * n) when the
/// clusters shrink by a fixed fraction per iteration, which these figures show.
struct PlocCounts {
    uint32_t iterations = 0;              ///< nearest-neighbour rounds until one cluster is left
    uint64_t cluster_visits = 0;          ///< clusters alive at the start of each round, summed
    uint64_t distance_evaluations = 0;    ///< merged-box areas computed, over all rounds
    uint32_t forced_rounds = 0;           ///< rounds where too few pairs agreed and neighbours were paired
    uint32_t balanced_subtrees = 0;       ///< subtrees past kMaxSahDepth rebuilt balanced by count
};

/// Builds a binary BVH bottom-up by parallel locally-ordered clustering (Meister and Bittner
/// 2018): primitives in Morton order, then rounds in which every cluster finds its nearest
/// neighbour (smallest merged box area) among options.ploc_radius clusters on each side, and
/// mutual nearest neighbours merge. Leaves are then cut where the SAH (leaves weighed in blocks
/// of options.sah_block) says a subtree of at most options.max_leaf primitives costs less as one
/// leaf. The tree is the same byte for byte on any options.threads. Child-order bytes hold the
/// split axis only (build_bvh adds the rest); `counts`, when given, receives the work done.
BvhData build_ploc(const BuildPrimitives& prims, const BvhBuildOptions& options, PlocCounts* counts = nullptr);

}  // namespace thicket
