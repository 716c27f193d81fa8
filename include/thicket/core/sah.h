#pragma once
/// SAH cost constants used for every reported SAH cost: cost(leaf) = C_isect * count,
/// cost(interior) = C_trav + sum over children of area(child)/area(node) * cost(child).
/// On the ground floor so that builders and figure walks need not include the Accel interface.

namespace thicket {

inline constexpr float kSahTraversalCost = 1.0f;
inline constexpr float kSahIntersectionCost = 1.0f;

}  // namespace thicket
