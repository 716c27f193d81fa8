#include "accel/dispatch.h"
#include "thicket/bsp/bsp.h"

namespace thicket {

namespace {

constexpr Choice<BspCost> kCosts[] = {{"sah", BspCost::Sah}, {"balance", BspCost::Balance}};
constexpr Choice<bool> kAxisFallback[] = {{"axis", true}, {"none", false}};

}  // namespace

void register_bsp(std::vector<AccelInfo>& registry) {
    using O = BspBuildOptions;
    const OptionFields<O> fields = {
        choice_field("cost",
                     "plane choice among the candidates: sah (fragments x area of each side's cell box cut to its "
                     "fragments' bounds) or balance (|front - back| + 8 x straddling)",
                     &O::cost, kCosts),
        int_field("candidates", "triangles whose planes are tried per node (evenly spaced over the node's fragments)",
                  &O::candidates, 1, 64),
        int_field("max-leaf", "nodes with more fragments are split while some candidate plane separates them",
                  &O::max_leaf, 1, 64),
        int_field("max-depth", "deeper nodes become leaves", &O::max_depth, 1, long(kBspMaxDepth)),
        choice_field("fallback",
                     "axis: where the node's own planes only peel (the best leaves > 7/8 of the fragments on one "
                     "side, as on curved surfaces), also try axis-aligned median planes; none: own planes only "
                     "(pure autopartition)",
                     &O::axis_fallback, kAxisFallback),
        int_field("fragment-budget",
                  "at most this many fragments per primitive in the whole tree (1: no triangle is ever cut); a split "
                  "that would exceed its share makes a leaf",
                  &O::fragment_budget, 1, 64),
    };
    // Every option value that changes a code path, combined so the family stays quick.
    AccelInfo info = accel_info({.name = "bsp",
                                 .partitioning = Partitioning::Space,
                                 .summary = "BSP tree by autopartition: planes of the scene's own triangles, "
                                            "straddlers cut into fragments",
                                 .variants = {"bsp", "bsp:cost=balance,fallback=none",
                                              "bsp:isect=watertight,max-leaf=4,candidates=4",
                                              "bsp:fragment-budget=2,max-depth=16"}},
                                fields);
    // Loading rebuilds and compares (Bsp's proving constructor): no cheaper proof covers clipping.
    set_build_and_load<Bsp>(info, fields, read_bsp);
    registry.push_back(std::move(info));
}

}  // namespace thicket
