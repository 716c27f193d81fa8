#include "accel/dispatch.h"
#include "bvh/builder_choices.h"
#include "thicket/obb/obb.h"

namespace thicket {

namespace {

constexpr Choice<ObbFit> kFits[] = {{"pca", ObbFit::Pca}, {"axes", ObbFit::Axes}};

/// The build options a parsed spec asks for.
ObbBuildOptions build_options(const AccelSpec& spec) {
    ObbBuildOptions o;
    o.bvh.builder = spec.choice("builder", kObjectBvhBuilders);
    o.bvh.max_leaf = int(spec.get_int("max-leaf"));
    read_optimize_options(spec, o.bvh);
    o.fit = spec.choice("fit", kFits);
    return o;
}

}  // namespace

void register_obb(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "obb";
    info.partitioning = Partitioning::Object;
    info.summary = "oriented bounding box tree (Rubin & Whitted 1980): a bvh's topology, every node refitted as a "
                   "rotated box (68-byte nodes), the ray moved into each box's frame";
    info.options = {
        choice_option("builder", "the bvh builder whose tree is refitted (see bvh; not sbvh: one box per primitive set)",
                      BvhBuilder::BinnedSah, kObjectBvhBuilders),
        {"max-leaf", "largest leaf of the bvh tree", "8", {}, 1, 255},
        choice_option("fit",
                      "orientation of each box: pca (principal axes of the node's points, or the world axes where "
                      "they enclose them in less area) or axes (the world axes: the bvh's own boxes, a baseline)",
                      ObbFit::Pca, kFits),
    };
    for (OptionInfo& o : bvh_optimize_options()) info.options.push_back(std::move(o));
    info.variants = {"obb", "obb:fit=axes", "obb:builder=lbvh,max-leaf=1", "obb:isect=watertight"};
    info.threaded_build = true;
    set_build_and_load<Obb>(info, build_options, read_obb);
    registry.push_back(std::move(info));
}

}  // namespace thicket
