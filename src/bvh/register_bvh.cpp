#include "accel/dispatch.h"
#include "bvh/builder_choices.h"
#include "thicket/bvh/bvh.h"
#include "thicket/bvh/bvh_double.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

// A new traversal is one line here, a new builder one line in bvh/builder_choices.h: the listing,
// the parser and read_settings() all read these tables.
constexpr Choice<BvhTraversal> kTraversals[] = {
    {"recursive", BvhTraversal::Recursive},
    {"stack", BvhTraversal::Stack},
    {"ordered-distance", BvhTraversal::OrderedDistance},
    {"ordered-axis", BvhTraversal::OrderedAxis},
    {"ordered-centroid", BvhTraversal::OrderedCentroid},
};

using BvhSettings = BuildAndTraversal<BvhBuildOptions, BvhTraversal, BvhTraversal::OrderedDistance>;

// Every object-partition builder with every traversal; sbvh (the slowest build: 11 s on the
// dragon, 32 s with alpha=0, one thread) with the default traversal and, replicating up to 2N
// references into one-triangle leaves, with the one that reads the stored split axis.
// ploc's tree is traversed like any other: ordered-axis (its stored split axis) here and the
// radius=1 variant below, not all five traversals (CI time).
std::vector<std::string> bvh_variants() {
    std::vector<std::string> variants;
    for (const auto& builder : kObjectBvhBuilders)
        for (const auto& traversal : kTraversals)
            if (builder.value != BvhBuilder::Ploc)
                variants.push_back(std::string("bvh:builder=") + builder.name + ",traversal=" + traversal.name);
    variants.insert(variants.end(), {
        "bvh:builder=ploc,traversal=ordered-axis",
        "bvh:builder=binned-sah,traversal=ordered-distance,isect=watertight",
        "bvh:builder=binned-sah,bins=32,max-leaf=1,traversal=ordered-distance",
        "bvh:builder=binned-sah,optimize=reinsertion,traversal=ordered-axis",
        "bvh:builder=sweep-sah,sah-block=4,traversal=ordered-distance",
        "bvh:builder=lbvh,optimize=reinsertion,max-leaf=1,traversal=ordered-centroid",
        "bvh:builder=sbvh,traversal=ordered-distance",
        "bvh:budget=1,builder=sbvh,max-leaf=1,traversal=ordered-axis",
        "bvh:builder=ploc,radius=1,max-leaf=1,sah-block=4,traversal=ordered-distance",
    });
    return variants;
}

}  // namespace

void register_bvh(std::vector<AccelInfo>& registry) {
    const OptionFields<BvhSettings> fields = join_fields(
        fields_in(&BvhSettings::build,
                  {builder_field(kBvhBuilderHelp, kBvhBuilders), bins_field(),
                   max_leaf_field("largest leaf; bigger nodes are split even when the SAH would stop"),
                   sah_block_field()}),
        OptionFields<BvhSettings>{
            choice_field("traversal",
                         "recursive (the slide), stack (iterative), or ordered: nearest child by entry distance, by "
                         "the ray's sign on the stored split axis, or on the axis of widest child-centroid "
                         "separation",
                         &BvhSettings::traversal, kTraversals),
            listed_field<BvhSettings>(precision_option())},
        fields_in(&BvhSettings::build, join_fields(sbvh_ploc_fields(), optimize_fields())));
    AccelInfo info = accel_info({.name = "bvh",
                                 .partitioning = Partitioning::Object,
                                 .summary = "the lecture's BVH: 32-byte nodes, node pool, in-place partition, SAH "
                                            "leaves",
                                 .variants = bvh_variants(),
                                 .threaded_build = true},
                                fields);
    info.build = [fields](const Scene& scene, const AccelSpec& spec) -> std::unique_ptr<Accel> {
        const BvhSettings s = read_settings(fields, spec);
        if (wants_double(spec))
            return with_double_triangles(scene, spec, [&](auto prims) -> std::unique_ptr<Accel> {
                return std::make_unique<BvhD<decltype(prims)::kTest>>(std::move(prims), s.build, s.traversal);
            });
        return make_structure<Bvh>(scene, spec, s.build, s.traversal);
    };
    info.load = [fields](std::istream& in, const Scene& scene, const AccelSpec& spec) -> std::unique_ptr<Accel> {
        // A double BVH is never saved (Accel::save refuses it), so no valid file names one.
        if (wants_double(spec)) throw Error(spec.str() + ": a precision=double BVH cannot be loaded from a file");
        return make_structure<Bvh>(scene, spec, read_bvh(in, scene.primitive_count()),
                                   read_settings(fields, spec).traversal);
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
