#include "accel/dispatch.h"
#include "thicket/bsp/bsp.h"

namespace thicket {

namespace {

constexpr Choice<BspCost> kCosts[] = {{"sah", BspCost::Sah}, {"balance", BspCost::Balance}};
constexpr Choice<bool> kAxisFallback[] = {{"axis", true}, {"none", false}};

BspBuildOptions build_options(const AccelSpec& spec) {
    BspBuildOptions o;
    o.cost = spec.choice("cost", kCosts);
    o.candidates = int(spec.get_int("candidates"));
    o.max_leaf = int(spec.get_int("max-leaf"));
    o.max_depth = int(spec.get_int("max-depth"));
    o.fragment_budget = int(spec.get_int("fragment-budget"));
    o.axis_fallback = spec.choice("fallback", kAxisFallback);
    return o;
}

}  // namespace

void register_bsp(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "bsp";
    info.partitioning = Partitioning::Space;
    info.summary = "BSP tree by autopartition: planes of the scene's own triangles, straddlers cut into fragments";
    const BspBuildOptions d;
    info.options = {
        choice_option("cost",
                      "plane choice among the candidates: sah (fragments x area of each side's cell box cut to its "
                      "fragments' bounds) or balance (|front - back| + 8 x straddling)",
                      BspCost::Sah, kCosts),
        {"candidates", "triangles whose planes are tried per node (evenly spaced over the node's fragments)",
         std::to_string(d.candidates), {}, 1, 64},
        {"max-leaf", "nodes with more fragments are split while some candidate plane separates them",
         std::to_string(d.max_leaf), {}, 1, 64},
        {"max-depth", "deeper nodes become leaves", std::to_string(d.max_depth), {}, 1, long(kBspMaxDepth)},
        choice_option("fallback",
                      "axis: where the node's own planes only peel (the best leaves > 7/8 of the fragments on one "
                      "side, as on curved surfaces), also try axis-aligned median planes; none: own planes only "
                      "(pure autopartition)",
                      true, kAxisFallback),
        {"fragment-budget",
         "at most this many fragments per primitive in the whole tree (1: no triangle is ever cut); a split "
         "that would exceed its share makes a leaf",
         std::to_string(d.fragment_budget), {}, 1, 64},
    };
    // Every option value that changes a code path, combined so the family stays quick.
    info.variants = {
        "bsp",
        "bsp:cost=balance,fallback=none",
        "bsp:isect=watertight,max-leaf=4,candidates=4",
        "bsp:fragment-budget=2,max-depth=16",
    };
    info.build = [](const Scene& scene, const AccelSpec& spec) {
        return make_structure<Bsp>(scene, spec, build_options(spec));
    };
    // Loading rebuilds and compares (Bsp's proving constructor): no cheaper proof covers clipping.
    info.load = [](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        return make_structure<Bsp>(scene, spec, read_bsp(in, scene.primitive_count()), build_options(spec));
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
