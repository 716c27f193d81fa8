#pragma once
/// The binary BVH builders by name: one table for every structure whose `builder=` option picks
/// one (`bvh`, and `bvh8`, which collapses their trees). A new builder is one line here.
#include "thicket/accel/registry.h"
#include "thicket/bvh/build.h"

namespace thicket {

inline constexpr Choice<BvhBuilder> kBvhBuilders[] = {
    {"midpoint", BvhBuilder::Midpoint},
    {"binned-sah", BvhBuilder::BinnedSah},
    {"sweep-sah", BvhBuilder::SweepSah},
    {"lbvh", BvhBuilder::Lbvh},
};

}  // namespace thicket
