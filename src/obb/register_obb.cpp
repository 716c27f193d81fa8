#include "accel/dispatch.h"
#include "bvh/builder_choices.h"
#include "thicket/obb/obb.h"

namespace thicket {

namespace {

constexpr Choice<ObbFit> kFits[] = {{"pca", ObbFit::Pca}, {"axes", ObbFit::Axes}};

}  // namespace

void register_obb(std::vector<AccelInfo>& registry) {
    using O = ObbBuildOptions;
    const OptionFields<O> fields = join_fields(
        fields_in(&O::bvh, {builder_field("the bvh builder whose tree is refitted (see bvh; not sbvh: one box per "
                                          "primitive set)",
                                          kObjectBvhBuilders),
                            max_leaf_field("largest leaf of the bvh tree")}),
        OptionFields<O>{choice_field("fit",
                                     "orientation of each box: pca (principal axes of the node's points, or the "
                                     "world axes where they enclose them in less area) or axes (the world axes: the "
                                     "bvh's own boxes, a baseline)",
                                     &O::fit, kFits)},
        fields_in(&O::bvh, optimize_fields()));
    AccelInfo info = accel_info({.name = "obb",
                                 .partitioning = Partitioning::Object,
                                 .summary = "oriented bounding box tree (Rubin & Whitted 1980): a bvh's topology, "
                                            "every node refitted as a rotated box (68-byte nodes), the ray moved into "
                                            "each box's frame",
                                 .variants = {"obb", "obb:fit=axes", "obb:builder=lbvh,max-leaf=1",
                                              "obb:isect=watertight"},
                                 .threaded_build = true},
                                fields);
    set_build_and_load<Obb>(info, fields, read_obb);
    registry.push_back(std::move(info));
}

}  // namespace thicket
