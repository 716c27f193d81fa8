// Registers `bvh8`: its options, and one conformance variant per ISA this CPU runs.
#include "accel/dispatch.h"
#include "bvh/builder_choices.h"
#include "thicket/bvh8/bvh8.h"

#include <string>
#include <string_view>

namespace thicket {

namespace {

constexpr Choice<std::string_view> kIsas[] = {
    {"auto", "auto"}, {"scalar", "scalar"}, {"sse", "sse"}, {"avx2", "avx2"}, {"avx512", "avx512"},
};

Bvh8Options bvh8_options(const AccelSpec& spec) {
    Bvh8Options o;
    o.binary.builder = spec.choice("builder", kBvhBuilders);
    o.binary.bins = int(spec.get_int("bins"));
    o.binary.max_leaf = int(spec.get_int("max-leaf"));
    o.binary.threads = spec.threads;
    o.merge_below = uint32_t(spec.get_int("leaf-merge"));
    o.isa = bvh8::resolve_isa(std::string(spec.choice("isa", kIsas)));
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
        {"bins", "bins per axis for binned-sah", "16", {}, 2, 256},
        {"max-leaf", "largest binary leaf (one 4-triangle block per 4)", "4", {}, 1, 255},
        {"leaf-merge",
         "binary subtrees of at most this many primitives become one leaf: 4 fills one block; 8 trades "
         "speed for memory (fewer, fuller nodes)",
         "4", {}, 0, 64},
        choice_option("isa",
                      "traversal kernels: auto (the CPU's best, capped by THICKET_ISA=scalar|sse|avx2|avx512) or "
                      "one level",
                      std::string_view("auto"), kIsas),
    };
    for (bvh8::Isa isa : bvh8::cpu_isas()) {
        const std::string level = bvh8::isa_name(isa);
        info.variants.push_back("bvh8:isa=" + level);
        info.variants.push_back("bvh8:isa=" + level + ",isect=watertight");
    }
    info.variants.push_back("bvh8:builder=sweep-sah,max-leaf=8,leaf-merge=8");
    info.variants.push_back("bvh8:builder=midpoint,max-leaf=1");
    info.variants.push_back("bvh8:builder=lbvh");

    info.threaded_build = true;
    info.build = [](const Scene& scene, const AccelSpec& spec) {
        const Bvh8Options options = bvh8_options(spec);
        return with_primitives(scene, spec, [&](auto prims) -> std::unique_ptr<Accel> {
            return std::make_unique<Bvh8<decltype(prims)>>(std::move(prims), options);
        });
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
