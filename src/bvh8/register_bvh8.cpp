// Registers `bvh8`: its options, and one conformance variant per ISA this CPU runs.
#include "accel/dispatch.h"
#include "bvh/builder_choices.h"
#include "thicket/bvh8/bvh8.h"

#include <string>
#include <utility>

namespace thicket {

namespace {

constexpr Choice<bool> kOnOff[] = {{"on", true}, {"off", false}};
constexpr Choice<bool> kNodeLayouts[] = {{"full", false}, {"compressed", true}};

// The default of `bins`, which the quality presets set too.
constexpr const char* kDefaultBins = "16";

/// The `isa` option resolved (auto: the CPU's best): what the build and the kernels listing use.
Isa chosen_isa(const AccelSpec& spec) { return resolve_isa(spec.get("isa"), "bvh8"); }

Bvh8Options bvh8_options(const AccelSpec& spec) {
    Bvh8Options o;
    read_binary_bvh_options(spec, o.binary);
    o.merge_below = uint32_t(spec.get_int("leaf-merge"));
    o.isa = chosen_isa(spec);
    o.packets = spec.choice("packets", kOnOff);
    o.compressed = spec.choice("nodes", kNodeLayouts);
    return o;
}

/// The `isa` option: kAutoIsa, then the levels of the one table kIsaLevels (which
/// resolve_isa() reads the value with).
OptionInfo isa_option() {
    std::string levels;
    for (const Choice<Isa>& c : kIsaLevels) levels += (levels.empty() ? "" : "|") + std::string(c.name);
    OptionInfo o = choice_option("isa",
                                 std::string("traversal kernels: ") + kAutoIsa +
                                     " (the CPU's best, capped by THICKET_ISA=" + levels + ") or one level",
                                 Isa::Scalar, kIsaLevels);
    o.choices.insert(o.choices.begin(), kAutoIsa);
    o.default_value = kAutoIsa;
    return o;
}

}  // namespace

void register_bvh8(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "bvh8";
    info.summary = "production BVH: 8-wide SoA nodes, 4-triangle blocks, SIMD kernels chosen by cpuid";
    info.partitioning = Partitioning::Object;
    info.options = {
        choice_option("builder", "the binary BVH builder whose tree is collapsed to 8 wide", BvhBuilder::BinnedSah,
                      kBvhBuilders),
        {"bins", "bins per axis for binned-sah", kDefaultBins, {}, 2, 256},
        preset_option("quality",
                      "builder preset: low (fastest build), medium (parallel binned SAH), high (spatial splits, "
                      "then reinsertion; alpha and budget apply); custom = the builder, bins and optimize keys as "
                      "given. A preset sets the keys listed below (another value of one of them is an error); the "
                      "spec records them, with quality=custom",
                      {{"custom", {}},
                       {"low", {{"builder", "lbvh"}, {"bins", kDefaultBins}, {"optimize", "none"}}},
                       {"medium", {{"builder", "binned-sah"}, {"bins", kDefaultBins}, {"optimize", "none"}}},
                       {"high", {{"builder", "sbvh"}, {"bins", kDefaultBins}, {"optimize", "reinsertion"}}}}),
        {"max-leaf", "largest binary leaf (one 4-triangle block per 4)", "4", {}, 1, 255},
        sah_block_option("4"),
        {"leaf-merge",
         "binary subtrees of at most this many primitives become one leaf: 4 fills one block; 8 trades "
         "speed for memory (fewer, fuller nodes)",
         "4", {}, 0, 64},
        isa_option(),
        choice_option("packets",
                      "batches marked coherent (camera rays in tiles: `thicket render`, `trace --coherent`, the "
                      "bench's primary set) are traced 16 rays at a time through the packet kernels; same answers",
                      true, kOnOff),
        choice_option("nodes",
                      "node layout: full (256-byte nodes of float boxes) or compressed (96-byte nodes, each "
                      "child plane 8 bits relative to its node's box, rounded outward: the same hits in 0.4x "
                      "the node memory)",
                      false, kNodeLayouts),
    };
    for (OptionInfo& o : sbvh_options()) info.options.push_back(std::move(o));
    for (OptionInfo& o : bvh_optimize_options()) info.options.push_back(std::move(o));
    for (Isa isa : cpu_isas()) {
        const std::string level = isa_name(isa);
        info.variants.push_back("bvh8:isa=" + level);
        info.variants.push_back("bvh8:isa=" + level + ",isect=watertight");
        info.variants.push_back("bvh8:isa=" + level + ",nodes=compressed");
    }
    info.variants.push_back("bvh8:builder=sweep-sah,max-leaf=8,leaf-merge=8");
    info.variants.push_back("bvh8:builder=midpoint,max-leaf=1");
    info.variants.push_back("bvh8:builder=lbvh");
    info.variants.push_back("bvh8:builder=ploc");
    info.variants.push_back("bvh8:quality=low");
    info.variants.push_back("bvh8:quality=high");
    info.variants.push_back("bvh8:quality=high,nodes=compressed,isect=watertight");

    info.threaded_build = true;
    info.build = [](const Scene& scene, const AccelSpec& spec) {
        return make_structure<Bvh8>(scene, spec, bvh8_options(spec));
    };
    info.kernels = [](const AccelSpec& spec) { return std::string(isa_name(chosen_isa(spec))); };
    info.load = [](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        bvh8::SavedTree saved = bvh8::read_tree(in, scene.primitive_count());
        return make_structure<Bvh8>(scene, spec, bvh8_options(spec), std::move(saved));
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
