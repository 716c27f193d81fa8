#include "accel/dispatch.h"
#include "bvh/builder_choices.h"
#include "thicket/bvh/bvh.h"
#include "thicket/bvh/bvh_double.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

// A new traversal is one line here, a new builder one line in bvh/builder_choices.h: the listing,
// the parser and build_options() all read these tables.
constexpr Choice<BvhTraversal> kTraversals[] = {
    {"recursive", BvhTraversal::Recursive},
    {"stack", BvhTraversal::Stack},
    {"ordered-distance", BvhTraversal::OrderedDistance},
    {"ordered-axis", BvhTraversal::OrderedAxis},
    {"ordered-centroid", BvhTraversal::OrderedCentroid},
};

BvhBuildOptions build_options(const AccelSpec& spec) {
    BvhBuildOptions o;
    read_binary_bvh_options(spec, o);
    return o;
}

BvhTraversal traversal_option(const AccelSpec& spec) { return spec.choice("traversal", kTraversals); }

}  // namespace

void register_bvh(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "bvh";
    info.summary = "the lecture's BVH: 32-byte nodes, node pool, in-place partition, SAH leaves";
    info.partitioning = Partitioning::Object;
    info.options = {
        choice_option("builder", kBvhBuilderHelp, BvhBuilder::BinnedSah, kBvhBuilders),
        {"bins", "bins per axis for binned-sah", "8", {}, 2, 256},
        {"max-leaf", "largest leaf; bigger nodes are split even when the SAH would stop", "8", {}, 1, 255},
        sah_block_option("1"),
        choice_option("traversal",
                      "recursive (the slide), stack (iterative), or ordered: nearest child by entry distance, by "
                      "the ray's sign on the stored split axis, or on the axis of widest child-centroid separation",
                      BvhTraversal::OrderedDistance, kTraversals),
    };
    info.options.push_back(precision_option());
    for (OptionInfo& o : sbvh_options()) info.options.push_back(std::move(o));
    for (OptionInfo& o : bvh_optimize_options()) info.options.push_back(std::move(o));
    // Every object-partition builder with every traversal; sbvh (the slowest build: 11 s on the
    // dragon, 32 s with alpha=0, one thread) with the default traversal and, replicating up to 2N
    // references into one-triangle leaves, with the one that reads the stored split axis.
    // ploc's tree is traversed like any other: ordered-axis (its stored split axis) here and the
    // radius=1 variant below, not all five traversals (CI time).
    for (const auto& builder : kObjectBvhBuilders)
        for (const auto& traversal : kTraversals)
            if (builder.value != BvhBuilder::Ploc)
                info.variants.push_back(std::string("bvh:builder=") + builder.name + ",traversal=" + traversal.name);
    info.variants.push_back("bvh:builder=ploc,traversal=ordered-axis");
    info.variants.push_back("bvh:builder=binned-sah,traversal=ordered-distance,isect=watertight");
    info.variants.push_back("bvh:builder=binned-sah,bins=32,max-leaf=1,traversal=ordered-distance");
    info.variants.push_back("bvh:builder=binned-sah,optimize=reinsertion,traversal=ordered-axis");
    info.variants.push_back("bvh:builder=sweep-sah,sah-block=4,traversal=ordered-distance");
    info.variants.push_back("bvh:builder=lbvh,optimize=reinsertion,max-leaf=1,traversal=ordered-centroid");
    info.variants.push_back("bvh:builder=sbvh,traversal=ordered-distance");
    info.variants.push_back("bvh:budget=1,builder=sbvh,max-leaf=1,traversal=ordered-axis");
    info.variants.push_back("bvh:builder=ploc,radius=1,max-leaf=1,sah-block=4,traversal=ordered-distance");

    info.threaded_build = true;
    info.build = [](const Scene& scene, const AccelSpec& spec) -> std::unique_ptr<Accel> {
        if (wants_double(spec))
            return with_double_triangles(scene, spec, [&](auto prims) -> std::unique_ptr<Accel> {
                return std::make_unique<BvhD<decltype(prims)::kTest>>(std::move(prims), build_options(spec),
                                                                      traversal_option(spec));
            });
        return make_structure<Bvh>(scene, spec, build_options(spec), traversal_option(spec));
    };
    info.load = [](std::istream& in, const Scene& scene, const AccelSpec& spec) -> std::unique_ptr<Accel> {
        // A double BVH is never saved (Accel::save refuses it), so no valid file names one.
        if (wants_double(spec)) throw Error(spec.str() + ": a precision=double BVH cannot be loaded from a file");
        return make_structure<Bvh>(scene, spec, read_bvh(in, scene.primitive_count()), traversal_option(spec));
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
