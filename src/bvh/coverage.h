#pragma once
// Internal to the BVH: the proof that a primitive listed in several leaves (spatial splits) has
// every part of it inside one of those leaves' boxes (validate_bvh_bounds calls it).
#include <span>
#include <vector>

#include "thicket/bvh/build.h"

namespace thicket {

class CoverageProof {
public:
    /// Proves against `prim_bounds` and `clip` (empty: bounds intersected with the box).
    CoverageProof(std::span<const Aabb> prim_bounds, const ClipFunction& clip) : bounds_(prim_bounds), clip_(clip) {}

    /// Throws Error unless every point of primitive `prim` lies in one of `boxes` (its leaves'),
    /// or the proof would take more work than a tree the builder made ever needs.
    void check(uint32_t prim, std::span<const Aabb> boxes);

private:
    /// Bounds of the part of `prim` inside `region` (outward-rounded: contains the exact part);
    /// throws once the proof has clipped too often.
    Aabb piece(uint32_t prim, const Aabb& region);
    /// Whether the part of `prim` inside `region`, whose bounds are `part`, lies in `box`.
    bool inside(uint32_t prim, const Aabb& region, const Aabb& part, const Aabb& box);

    std::span<const Aabb> bounds_;
    const ClipFunction& clip_;
    size_t clips_ = 0, box_tests_ = 0;  ///< spent so far, over every primitive checked
};

}  // namespace thicket
