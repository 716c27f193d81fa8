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

/// The optimizers a built tree can be given (`optimize=`), shared likewise.
inline constexpr Choice<BvhOptimize> kBvhOptimizers[] = {
    {"none", BvhOptimize::None},
    {"reinsertion", BvhOptimize::Reinsertion},
};

/// The `optimize` and `passes` options of every structure built on the binary BVH.
inline std::vector<OptionInfo> bvh_optimize_options() {
    return {choice_option("optimize",
                          "after the build: none, or reinsertion (Bittner et al. 2013: the largest boxes moved to "
                          "where they add least area; never raises the SAH cost)",
                          BvhOptimize::None, kBvhOptimizers),
            {"passes", "optimize=reinsertion's budget: passes at most (each moves up to 5% of the nodes)", "3", {}, 1,
             100}};
}

}  // namespace thicket
