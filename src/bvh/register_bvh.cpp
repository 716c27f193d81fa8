#include "accel/dispatch.h"
#include "thicket/bvh/bvh.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

BvhBuildOptions build_options(const AccelSpec& spec) {
    BvhBuildOptions o;
    const std::string& b = spec.get("builder");
    o.builder = b == "midpoint" ? BvhBuilder::Midpoint : (b == "sweep-sah" ? BvhBuilder::SweepSah : BvhBuilder::BinnedSah);
    o.bins = int(spec.get_int("bins"));
    o.max_leaf = int(spec.get_int("max-leaf"));
    return o;
}

BvhTraversal traversal_option(const AccelSpec& spec) {
    const std::string& t = spec.get("traversal");
    if (t == "recursive") return BvhTraversal::Recursive;
    if (t == "stack") return BvhTraversal::Stack;
    if (t == "ordered-axis") return BvhTraversal::OrderedAxis;
    if (t == "ordered-centroid") return BvhTraversal::OrderedCentroid;
    return BvhTraversal::OrderedDistance;
}

}  // namespace

void register_bvh(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "bvh";
    info.summary = "the lecture's BVH: 32-byte nodes, node pool, in-place partition, SAH leaves";
    info.partitioning = Partitioning::Object;
    info.options = {
        {"builder", "split choice: longest-axis midpoint, binned SAH (Wald 2007), or a full SAH sweep",
         "binned-sah", {"midpoint", "binned-sah", "sweep-sah"}, 0, 0},
        {"bins", "bins per axis for binned-sah", "8", {}, 2, 256},
        {"max-leaf", "largest leaf; bigger nodes are split even when the SAH would stop", "8", {}, 1, 255},
        {"traversal",
         "recursive (the slide), stack (iterative), or ordered: nearest child by entry distance, by the ray's "
         "sign on the stored split axis, or on the axis of widest child-centroid separation",
         "ordered-distance", {"recursive", "stack", "ordered-distance", "ordered-axis", "ordered-centroid"}, 0, 0},
    };
    for (const char* builder : {"midpoint", "binned-sah", "sweep-sah"})
        for (const char* traversal : {"recursive", "stack", "ordered-distance", "ordered-axis", "ordered-centroid"})
            info.variants.push_back(std::string("bvh:builder=") + builder + ",traversal=" + traversal);
    info.variants.push_back("bvh:builder=binned-sah,traversal=ordered-distance,isect=watertight");
    info.variants.push_back("bvh:builder=binned-sah,bins=32,max-leaf=1,traversal=ordered-distance");

    info.build = [](const Scene& scene, const AccelSpec& spec) {
        return with_primitives(scene, spec, [&](auto prims) -> std::unique_ptr<Accel> {
            return std::make_unique<Bvh<decltype(prims)>>(std::move(prims), build_options(spec), traversal_option(spec));
        });
    };
    info.load = [](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        BvhData data = read_bvh(in, scene.primitive_count());
        return with_primitives(scene, spec, [&](auto prims) -> std::unique_ptr<Accel> {
            return std::make_unique<Bvh<decltype(prims)>>(std::move(prims), std::move(data), traversal_option(spec));
        });
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
