#pragma once
// Internal to the octree: how the builder sorts a cell's references into its eight children.
// The builder (build.cpp) and the load-time proof (validate_coverage.cpp) both use it, so the
// proof replays exactly the builder's classification.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "thicket/core/ray.h"
#include "thicket/octree/build.h"

namespace thicket::octree_detail {

/// A primitive's reference in a cell, with bounds of its part inside the cell: exact (what the
/// clip hook gives), or, when kLoose is set in `prim`, only known to enclose the part.
struct Ref {
    uint32_t prim;
    Aabb part;
};
inline constexpr uint32_t kLoose = 0x80000000u;

/// Whether [lo, hi] reaches beyond `plane` on both sides by more than the clip hook's outward
/// rounding (two ulps), so that the part really has points on either side.
inline bool straddles(float lo, float hi, float plane) {
    const float below = std::nextafter(std::nextafter(plane, -kInfinity), -kInfinity);
    const float above = std::nextafter(std::nextafter(plane, kInfinity), kInfinity);
    return lo < below && hi > above;
}

class Distributor {
public:
    explicit Distributor(const OctreeClip& clip) : clip_(clip) {}

    /// Sorts the cell's references into its eight children, clipping as little as exactness
    /// allows. A part inside one child goes there unchanged. A loose part that crosses a
    /// mid-plane is first made exact by one clip against the cell; then place() splits it.
    void run(std::span<const Ref> refs, const Aabb& box) {
        for (auto& child : children) child.clear();
        for (int a = 0; a < 3; ++a) mid_[a] = octree_mid(box.min[a], box.max[a]);
        for (Ref r : refs) {
            if (crossed(r.part, 7) == 0) {
                children[side_bits(r.part, 7)].push_back(r);
                continue;
            }
            const uint32_t prim = r.prim & ~kLoose;
            const Aabb part = r.prim & kLoose ? clip_(prim, box) : r.part;
            if (!part.empty()) place(prim, part, box, 7, 0);
        }
    }

    std::array<std::vector<Ref>, 8> children;

private:
    /// Mask of the axes (among `axes`) on which the part reaches both halves of the cell.
    int crossed(const Aabb& part, int axes) const {
        int mask = 0;
        for (int a = 0; a < 3; ++a) mask |= int(part.min[a] <= mid_[a] && part.max[a] >= mid_[a]) << a;
        return mask & axes;
    }

    /// Child index bits, on `axes`, of a part that crosses none of their mid-planes.
    int side_bits(const Aabb& part, int axes) const {
        int c = 0;
        for (int a = 0; a < 3; ++a) c |= int(part.min[a] > mid_[a]) << a;
        return c & axes;
    }

    /// Places a primitive whose exact part in `region` (the cell, or the cell halved on the
    /// axes not in `axes`, on the sides given by `bits`) crosses mid-planes. Crossing one plane by more than rounding, it goes
    /// to both sides unclipped, marked loose: its exact box's extremes are points of the part,
    /// one on each side, and on the other axes all of it lies in one half. Otherwise it is
    /// clipped to both halves of the region on one crossed axis, and each half placed in turn
    /// (a quadrant of a part crossing two planes can be empty).
    void place(uint32_t prim, const Aabb& part, const Aabb& region, int axes, int bits) {
        const int mask = crossed(part, axes);
        if (mask == 0) {
            children[bits | side_bits(part, axes)].push_back({prim, part});
            return;
        }
        const int axis = mask & 1 ? 0 : (mask & 2 ? 1 : 2);
        const int others = axes & ~(1 << axis);
        if (mask == (1 << axis) && straddles(part.min[axis], part.max[axis], mid_[axis])) {
            for (const int upper : {0, 1}) {
                Aabb half = part;
                (upper ? half.min : half.max)[axis] = mid_[axis];
                children[bits | side_bits(part, others) | (upper << axis)].push_back({prim | kLoose, half});
            }
            return;
        }
        for (const int upper : {0, 1}) {
            Aabb half = region;
            (upper ? half.min : half.max)[axis] = mid_[axis];
            const Aabb sub = clip_(prim, half);
            if (!sub.empty()) place(prim, sub, half, others, bits | (upper << axis));
        }
    }

    const OctreeClip& clip_;
    Vec3 mid_;
};

}  // namespace thicket::octree_detail
