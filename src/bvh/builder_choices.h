#pragma once
/// The binary BVH builders by name, and the option fields of every structure built on the binary
/// BVH (`bvh`; `bvh8`, which collapses its trees; `obb`, which refits them). A new builder is one
/// line here.
#include "accel/option_fields.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh/build.h"

namespace thicket {

inline constexpr Choice<BvhBuilder> kBvhBuilders[] = {
    {"midpoint", BvhBuilder::Midpoint},
    {"binned-sah", BvhBuilder::BinnedSah},
    {"sweep-sah", BvhBuilder::SweepSah},
    {"lbvh", BvhBuilder::Lbvh},
    {"sbvh", BvhBuilder::Sbvh},
    {"ploc", BvhBuilder::Ploc},
};

/// The builders whose leaves list each primitive once (all but sbvh): for structures that refit
/// one box per primitive set (obb) and need the index array to be a permutation.
inline constexpr Choice<BvhBuilder> kObjectBvhBuilders[] = {
    {"midpoint", BvhBuilder::Midpoint},
    {"binned-sah", BvhBuilder::BinnedSah},
    {"sweep-sah", BvhBuilder::SweepSah},
    {"lbvh", BvhBuilder::Lbvh},
    {"ploc", BvhBuilder::Ploc},
};

/// The help of the `builder` option of the structures that take every builder.
inline constexpr const char* kBvhBuilderHelp =
    "split choice: longest-axis midpoint, binned SAH (Wald 2007), a full SAH sweep, the linear Morton-order builder "
    "(Karras 2012: fastest build, looser tree), or sbvh: spatial splits (Stich et al. 2009: SAH object splits against "
    "binned planes that cut the triangles straddling them, clipped exactly; a triangle may then sit in several "
    "leaves; alpha and budget below; one thread, the same tree on any), or ploc: bottom-up clustering (Meister and "
    "Bittner 2018: mutual nearest neighbours along the Morton curve merge, radius below; leaves cut by the SAH)";

/// The optimizers a built tree can be given (`optimize=`), shared likewise.
inline constexpr Choice<BvhOptimize> kBvhOptimizers[] = {
    {"none", BvhOptimize::None},
    {"reinsertion", BvhOptimize::Reinsertion},
};

/// The `builder` option over `table` (kBvhBuilders, or kObjectBvhBuilders for a structure
/// that needs each primitive in one leaf).
template <size_t N>
OptionField<BvhBuildOptions> builder_field(std::string help, const Choice<BvhBuilder> (&table)[N]) {
    return choice_field("builder", std::move(help), &BvhBuildOptions::builder, table);
}

/// The `bins` option of builder=binned-sah.
inline OptionField<BvhBuildOptions> bins_field() {
    return int_field("bins", "bins per axis for binned-sah", &BvhBuildOptions::bins, 2, 256);
}

/// The `max-leaf` option: the largest leaf of the binary tree.
inline OptionField<BvhBuildOptions> max_leaf_field(std::string help) {
    return int_field("max-leaf", std::move(help), &BvhBuildOptions::max_leaf, 1, 255);
}

/// The `sah-block` option (BvhBuildOptions::sah_block); its default is the structure's own (1
/// for the lecture's BVH, 4 for the structures that store leaves in 4-triangle blocks).
inline OptionField<BvhBuildOptions> sah_block_field() {
    return int_field("sah-block",
                     "primitives the SAH counts as one test: a leaf of n costs ceil(n / sah-block), and nodes of at "
                     "most " +
                         std::to_string(kBlockPackMax) +
                         " primitives are split by binned-sah, sweep-sah and sbvh (its object splits) only where "
                         "whole blocks go left, so the leaves fill their blocks (4: bvh8's 4-triangle blocks; 1: "
                         "every primitive counts)",
                     &BvhBuildOptions::sah_block, 1, 16);
}

/// The `alpha` and `budget` options of builder=sbvh and `radius` of builder=ploc, shared by every
/// structure that offers those builders.
inline OptionFields<BvhBuildOptions> sbvh_ploc_fields() {
    using O = BvhBuildOptions;
    return {real_field("alpha",
                       "builder=sbvh: spatial splits are tried only where the best object split's children overlap "
                       "by more than alpha times the root's surface area (Stich et al.'s alpha; 0: everywhere)",
                       &O::sbvh_alpha, "1e-3", 0.0, 1.0),
            real_field("budget",
                       "builder=sbvh: reference growth allowed, at most (1 + budget) N references in all, shared "
                       "down the tree in proportion to the nodes' references; 0: no spatial split",
                       &O::sbvh_budget, "0.3", 0.0, double(kMaxReferencesPerPrimitive - 1)),
            int_field("radius",
                      "builder=ploc: clusters searched on each side of a cluster, along the Morton curve, for its "
                      "nearest neighbour (larger: tighter trees, a build slower in proportion)",
                      &O::ploc_radius, 1, 256)};
}

/// The `optimize` and `passes` options of every structure built on the binary BVH, and the
/// build's threads.
inline OptionFields<BvhBuildOptions> optimize_fields() {
    using O = BvhBuildOptions;
    return {choice_field("optimize",
                         "after the build: none, or reinsertion (Bittner et al. 2013: the largest boxes moved to "
                         "where they add least area; never raises the SAH cost)",
                         &O::optimize, kBvhOptimizers),
            int_field("passes", "optimize=reinsertion's budget: passes at most (each moves up to 5% of the nodes)",
                      &O::optimize_passes, 1, 100),
            threads_field(&O::threads)};
}

}  // namespace thicket
