#pragma once
/// The reinsertion optimizer (Bittner, Hapala & Havran 2013) over a built binary BVH.
#include <cstddef>

#include "thicket/bvh/node.h"

namespace thicket {

/// What optimize_reinsertion did: the sum of interior half areas (the only part of the SAH cost
/// it changes) before and after, passes kept and nodes moved.
struct ReinsertionFigures {
    int passes = 0;
    size_t moves = 0;
    double area_before = 0.0, area_after = 0.0;
};

/// Runs up to `passes` passes over `bvh`; each takes the 5% of nodes with the largest boxes out
/// and puts each back where the interior area grows least. Never raises the SAH cost (a pass that
/// would, through rounding, is undone), keeps the depth within kMaxSahDepth, leaves every leaf as
/// it is, and lays the tree out again in the lecture's form. Deterministic (one thread).
ReinsertionFigures optimize_reinsertion(BvhData& bvh, int passes);

}  // namespace thicket
