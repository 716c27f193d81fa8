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

/// A candidate plane's best cost and where the primitives lying in it go.
struct KdPlaneCost {
    float cost = 0.0f;
    bool planar_left = true;
};

/// Prices the candidate planes on one axis of one voxel: a plane at `pos` with `nl` primitives
/// reaching below it, `np` lying in it and `nr` reaching above it (a straddling primitive counts
/// on both sides). The voxel's area and extents are computed once, since a sweep prices every
/// event position. Both builders and the tests' naive reference price planes with this.
class KdPlanePricer {
public:
    KdPlanePricer(const KdCostModel& c, const Aabb& voxel, int axis)
        : c_(c), lo_(voxel.min[axis]), hi_(voxel.max[axis]) {
        const float area = voxel.half_area();
        const float eb = voxel.max[(axis + 1) % 3] - voxel.min[(axis + 1) % 3];
        const float ec = voxel.max[(axis + 2) % 3] - voxel.min[(axis + 2) % 3];
        valid_ = area > 0.0f;
        inv_area_ = valid_ ? 1.0f / area : 0.0f;
        side_sum_ = eb + ec;
        face_ = eb * ec;
    }

    /// Returns false when the plane may not be used: the voxel has no area, or the plane is a
    /// face of the voxel and does not separate anything (a child equal to its parent would
    /// recurse forever: only splitting off the primitives lying in a face is allowed there).
    /// Ties between the two sides go left.
    bool price(float pos, uint32_t nl, uint32_t np, uint32_t nr, KdPlaneCost& out) const {
        if (!valid_) return false;
        const bool face = !(pos > lo_ && pos < hi_);
        const bool left_ok = !face || (nl + np > 0 && nr > 0);
        const bool right_ok = !face || (nl > 0 && nr + np > 0);
        if (!left_ok && !right_ok) return false;
        const float pl = ((pos - lo_) * side_sum_ + face_) * inv_area_;  // A(V_L) / A(V)
        const float pr = ((hi_ - pos) * side_sum_ + face_) * inv_area_;
        const float to_left = left_ok ? cost(pl, pr, nl + np, nr) : 0.0f;
        const float to_right = !right_ok ? 0.0f : (np == 0 && left_ok) ? to_left : cost(pl, pr, nl, nr + np);
        out.planar_left = left_ok && (!right_ok || to_left <= to_right);
        out.cost = out.planar_left ? to_left : to_right;
        return true;
    }

private:
    float cost(float pl, float pr, uint32_t nl, uint32_t nr) const {
        const float c = c_.traversal + c_.intersection * (pl * float(nl) + pr * float(nr));
        return (nl == 0 || nr == 0) ? c * (1.0f - c_.empty_bonus) : c;
    }

    KdCostModel c_;
    float lo_, hi_;
    bool valid_;
    float inv_area_, side_sum_, face_;
};

/// One plane priced on its own (KdPlanePricer::price).
inline bool kd_plane_cost(const KdCostModel& c, const Aabb& voxel, int axis, float pos, uint32_t nl, uint32_t np,
                          uint32_t nr, KdPlaneCost& out) {
    return KdPlanePricer(c, voxel, axis).price(pos, nl, np, nr, out);
}

}  // namespace thicket
