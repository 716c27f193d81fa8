// Registers `bvh8`: its options, and one conformance variant per ISA this CPU runs.
#include "accel/dispatch.h"
#include "bvh/builder_choices.h"
#include "thicket/bvh8/bvh8.h"
#include "thicket/core/error.h"

#include <string>
#include <utility>

namespace thicket {

namespace {

constexpr Choice<bool> kOnOff[] = {{"on", true}, {"off", false}};
constexpr Choice<bool> kNodeLayouts[] = {{"full", false}, {"compressed", true}};
constexpr Choice<bvh8::TreeSource> kTreeSources[] = {{"thicket", bvh8::TreeSource::Thicket},
                                                     {"embree-medium", bvh8::TreeSource::EmbreeMedium},
                                                     {"embree-high", bvh8::TreeSource::EmbreeHigh}};

// The default of `bins` (Bvh8Options' binary.bins), which the quality presets set too.
constexpr const char* kDefaultBins = "16";

/// The `isa` option resolved (auto: the CPU's best): what the build and the kernels listing use.
Isa chosen_isa(const AccelSpec& spec) { return resolve_isa(spec.get("isa"), "bvh8"); }

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

/// Every ISA this CPU runs, with each triangle test and node layout; then the builders, presets
/// and leaf shapes on the best one.
std::vector<std::string> bvh8_variants() {
    std::vector<std::string> variants;
    for (Isa isa : cpu_isas())
        for (const char* more : {"", ",isect=watertight", ",nodes=compressed"})
            variants.push_back("bvh8:isa=" + std::string(isa_name(isa)) + more);
    variants.insert(variants.end(), {
        "bvh8:builder=sweep-sah,max-leaf=8,leaf-merge=8",
        "bvh8:builder=midpoint,max-leaf=1",
        "bvh8:builder=lbvh",
        "bvh8:builder=ploc",
        "bvh8:quality=low",
        "bvh8:quality=high",
        "bvh8:quality=high,nodes=compressed,isect=watertight",
    });
    return variants;
}

/// tree=embree-* has Embree build the tree: a key of our builder set away from its default would
/// do nothing, so it is refused (the keys that still apply: the kernels', the layout's, the test's).
void refuse_unused_builder_keys(const AccelSpec& spec) {
    if (spec.get("tree") == "thicket") return;
    for (const OptionInfo& o : spec.info->options) {
        if (o.key == "tree" || o.key == "isa" || o.key == "packets" || o.key == "nodes" || o.key == "isect" ||
            o.key == "quality")
            continue;
        const std::string& value = spec.get(o.key);
        if (value != o.default_value)
            throw Error("bvh8: tree=" + spec.get("tree") + " builds Embree's tree, so " + o.key + "=" + value +
                        " would do nothing (this is our builder's key): leave it at " + o.default_value);
    }
}

}  // namespace

void register_bvh8(std::vector<AccelInfo>& registry) {
    using O = Bvh8Options;
    const OptionFields<O> fields = join_fields(
        fields_in(&O::binary,
                  {builder_field("the binary BVH builder whose tree is collapsed to 8 wide", kBvhBuilders),
                   bins_field()}),
        OptionFields<O>{listed_field<O>(preset_option(
            "quality",
            "builder preset: low (fastest build), medium (parallel binned SAH), high (spatial splits, then "
            "reinsertion; alpha and budget apply); custom = the builder, bins and optimize keys as given. A preset "
            "sets the keys listed below (another value of one of them is an error); the spec records them, with "
            "quality=custom",
            {{"custom", {}},
             {"low", {{"builder", "lbvh"}, {"bins", kDefaultBins}, {"optimize", "none"}}},
             {"medium", {{"builder", "binned-sah"}, {"bins", kDefaultBins}, {"optimize", "none"}}},
             {"high", {{"builder", "sbvh"}, {"bins", kDefaultBins}, {"optimize", "reinsertion"}}}}))},
        fields_in(&O::binary, {max_leaf_field("largest binary leaf (one 4-triangle block per 4)"), sah_block_field()}),
        OptionFields<O>{
            int_field("leaf-merge",
                      "binary subtrees of at most this many primitives become one leaf: 4 fills one block; 8 trades "
                      "speed for memory (fewer, fuller nodes)",
                      &O::merge_below, 0, 64),
            custom_field<O>(isa_option(), [](const AccelSpec& spec, O& o) { o.isa = chosen_isa(spec); }),
            choice_field("packets",
                         "batches marked coherent (camera rays in tiles: `thicket render`, `trace --coherent`, the "
                         "bench's primary set) are traced 16 rays at a time through the packet kernels; same answers",
                         &O::packets, kOnOff),
            choice_field("nodes",
                         "node layout: full (256-byte nodes of float boxes) or compressed (96-byte nodes, each child "
                         "plane 8 bits relative to its node's box, rounded outward: the same hits in 0.4x the node "
                         "memory)",
                         &O::compressed, kNodeLayouts),
            choice_field("tree",
                         "who builds the tree: thicket (the builder keys above), or Embree's own builder "
                         "(rtcBuildBVH: embree-medium binned SAH, embree-high with its spatial splits) writing bvh8 "
                         "nodes and blocks, traced by bvh8's kernels: the bench's split of the gap to Embree into tree "
                         "and kernel (our builder's keys must then keep their defaults). Only `thicket bench` links "
                         "Embree; elsewhere embree-* is an error",
                         &O::tree, kTreeSources)},
        fields_in(&O::binary, join_fields(sbvh_ploc_fields(), optimize_fields())));
    AccelInfo info = accel_info({.name = "bvh8",
                                 .partitioning = Partitioning::Object,
                                 .summary = "production BVH: 8-wide SoA nodes, 4-triangle blocks, SIMD kernels chosen "
                                            "by cpuid",
                                 .variants = bvh8_variants(),
                                 .threaded_build = true},
                                fields);
    info.build = [fields](const Scene& scene, const AccelSpec& spec) {
        refuse_unused_builder_keys(spec);
        return make_structure<Bvh8>(scene, spec, read_settings(fields, spec));
    };
    info.kernels = [](const AccelSpec& spec) { return std::string(isa_name(chosen_isa(spec))); };
    info.load = [fields](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        bvh8::SavedTree saved = bvh8::read_tree(in, scene.primitive_count());
        return make_structure<Bvh8>(scene, spec, read_settings(fields, spec), std::move(saved));
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
