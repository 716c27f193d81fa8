#pragma once
/// The kD-tree builders' cost model (Wald & Havran 2006): a split plane is judged by
///   lambda * (K_T + K_I * (A(V_L) * N_L + A(V_R) * N_R) / A(V)),
/// with lambda = 1 - empty_bonus when one side holds no primitive, and a node stays a leaf when
/// the best plane costs at least K_I * N. Primitives lying in the plane go to the cheaper side.
#include <cstdint>

#include "thicket/core/aabb.h"

namespace thicket {

struct KdCostModel {
    float traversal = 1.0f;     ///< K_T: one node step
    float intersection = 1.5f;  ///< K_I: one primitive test (Moller-Trumbore plus the plausibility check)
    float empty_bonus = 0.2f;   ///< lambda = 0.8 when a side is empty: cutting off empty space pays
};

inline float kd_leaf_cost(const KdCostModel& c, uint32_t count) { return c.intersection * float(count); }

/// Cost of a split of `voxel` (half-area `area`) into children of half-areas `left_area` and
/// `right_area` holding `nl` and `nr` primitives.
inline float kd_split_cost(const KdCostModel& c, float left_area, float right_area, float area, uint32_t nl,
                           uint32_t nr) {
    const float cost = c.traversal + c.intersection * (left_area * float(nl) + right_area * float(nr)) / area;
    return (nl == 0 || nr == 0) ? cost * (1.0f - c.empty_bonus) : cost;
}

/// A candidate plane's best cost and where the primitives lying in it go.
struct KdPlaneCost {
    float cost = 0.0f;
    bool planar_left = true;
};

/// Evaluates the plane `pos` on `axis` through `voxel` with `nl` primitives reaching below it,
/// `np` lying in it and `nr` reaching above it (a straddling primitive counts on both sides).
/// Returns false when the plane may not be used: the voxel has no area, or the plane is a face of
/// the voxel and does not separate anything (that would make a child equal to its parent and
/// recurse forever: only splitting off the primitives lying in a face is allowed there).
/// Ties between the two sides go left. Both builders and the tests' reference use this.
inline bool kd_plane_cost(const KdCostModel& c, const Aabb& voxel, int axis, float pos, uint32_t nl, uint32_t np,
                          uint32_t nr, KdPlaneCost& out) {
    const float area = voxel.half_area();
    if (!(area > 0.0f)) return false;
    Aabb left = voxel, right = voxel;
    left.max[axis] = pos;
    right.min[axis] = pos;
    const float la = left.half_area(), ra = right.half_area();
    const bool face = !(pos > voxel.min[axis] && pos < voxel.max[axis]);
    const bool left_ok = !face || (nl + np > 0 && nr > 0);
    const bool right_ok = !face || (nl > 0 && nr + np > 0);
    if (!left_ok && !right_ok) return false;
    const float to_left = left_ok ? kd_split_cost(c, la, ra, area, nl + np, nr) : 0.0f;
    const float to_right = right_ok ? kd_split_cost(c, la, ra, area, nl, nr + np) : 0.0f;
    out.planar_left = left_ok && (!right_ok || to_left <= to_right);
    out.cost = out.planar_left ? to_left : to_right;
    return true;
}

}  // namespace thicket
