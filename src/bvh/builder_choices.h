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

/// The `radius` option of builder=ploc, shared likewise.
inline OptionInfo ploc_radius_option() {
    return {"radius",
            "builder=ploc: clusters searched on each side of a cluster, along the Morton curve, for its nearest "
            "neighbour (larger: tighter trees, a build slower in proportion)",
            "16",
            {},
            1,
            256};
}

/// The `alpha` and `budget` options of builder=sbvh and `radius` of builder=ploc, shared by every
/// structure that offers them.
inline std::vector<OptionInfo> sbvh_options() {
    return {real_option("alpha",
                        "builder=sbvh: spatial splits are tried only where the best object split's children overlap "
                        "by more than alpha times the root's surface area (Stich et al.'s alpha; 0: everywhere)",
                        "1e-3", 0.0, 1.0),
            real_option("budget",
                        "builder=sbvh: reference growth allowed, at most (1 + budget) N references in all, shared "
                        "down the tree in proportion to the nodes' references; 0: no spatial split",
                        "0.3", 0.0, double(kMaxReferencesPerPrimitive - 1)),
            ploc_radius_option()};
}

/// The `sah-block` option (BvhBuildOptions::sah_block) with its default: 1 for the lecture's
/// BVH, 4 for the structures that store leaves in 4-triangle blocks.
inline OptionInfo sah_block_option(const char* default_value) {
    return {"sah-block",
            "primitives the SAH counts as one test: a leaf of n costs ceil(n / sah-block), and nodes of at most " +
                std::to_string(kBlockPackMax) +
                " primitives are split by binned-sah, sweep-sah and sbvh (its object splits) only where whole blocks "
                "go left, so the leaves fill their blocks (4: bvh8's 4-triangle blocks; 1: every primitive counts)",
            default_value,
            {},
            1,
            16};
}


/// The `optimize` and `passes` options of every structure built on the binary BVH.
inline std::vector<OptionInfo> bvh_optimize_options() {
    return {choice_option("optimize",
                          "after the build: none, or reinsertion (Bittner et al. 2013: the largest boxes moved to "
                          "where they add least area; never raises the SAH cost)",
                          BvhOptimize::None, kBvhOptimizers),
            {"passes", "optimize=reinsertion's budget: passes at most (each moves up to 5% of the nodes)", "3", {}, 1,
             100}};
}

/// Reads bvh_optimize_options() into `o`, and the build's threads.
inline void read_optimize_options(const AccelSpec& spec, BvhBuildOptions& o) {
    o.threads = spec.threads;
    o.optimize = spec.choice("optimize", kBvhOptimizers);
    o.optimize_passes = int(spec.get_int("passes"));
}

/// Reads the options of a structure built on the binary BVH with kBvhBuilders (bvh, bvh8): the
/// builder, bins, max-leaf, sah-block, the sbvh and ploc options and read_optimize_options().
inline void read_binary_bvh_options(const AccelSpec& spec, BvhBuildOptions& o) {
    o.builder = spec.choice("builder", kBvhBuilders);
    o.bins = int(spec.get_int("bins"));
    o.max_leaf = int(spec.get_int("max-leaf"));
    o.sah_block = uint32_t(spec.get_int("sah-block"));
    o.sbvh_alpha = spec.get_real("alpha");
    o.sbvh_budget = spec.get_real("budget");
    o.ploc_radius = uint32_t(spec.get_int("radius"));
    read_optimize_options(spec, o);
}

}  // namespace thicket
