#include "accel/dispatch.h"
#include "thicket/kdtree/kdtree.h"

namespace thicket {

namespace {

constexpr Choice<KdBuilder> kBuilders[] = {{"sah", KdBuilder::Sah}, {"median", KdBuilder::Median}};
constexpr Choice<KdTraversal> kTraversals[] = {{"stack", KdTraversal::Stack}, {"restart", KdTraversal::Restart}};

using KdSettings = BuildAndTraversal<KdBuildOptions, KdTraversal, KdTraversal::Stack>;

}  // namespace

void register_kdtree(std::vector<AccelInfo>& registry) {
    const OptionFields<KdSettings> fields = join_fields(
        fields_in(&KdSettings::build,
                  {choice_field("builder",
                                "sah: events sorted once, SAH sweep (K_T = 1, K_I = 1.5, empty-space bonus 0.8), "
                                "perfect splits, O(N log N); median: middle of the voxel's longest axis, the same "
                                "SAH decides when to stop",
                                &KdBuildOptions::builder, kBuilders)}),
        OptionFields<KdSettings>{choice_field("traversal",
                                              "stack: near/far with a stack (Havran's TA_rec_B); restart: "
                                              "kd-restart, no stack (Foley & Sugerman 2005)",
                                              &KdSettings::traversal, kTraversals)});
    // Every option value in three variants: the default, restart on the same tree, and the other
    // builder with the other triangle test.
    AccelInfo info = accel_info(
        {.name = "kdtree",
         .partitioning = Partitioning::Space,
         .summary = "SAH kD-tree (Wald & Havran 2006, O(N log N), perfect splits): 8-byte nodes, mailboxing",
         .variants = {"kdtree:builder=sah,traversal=stack", "kdtree:builder=sah,traversal=restart",
                      "kdtree:builder=median,traversal=stack,isect=watertight"}},
        fields);
    info.build = [fields](const Scene& scene, const AccelSpec& spec) {
        const KdSettings s = read_settings(fields, spec);
        return make_structure<KdTree>(scene, spec, s.build, s.traversal);
    };
    info.load = [fields](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        const KdSettings s = read_settings(fields, spec);
        return make_structure<KdTree>(scene, spec, read_kdtree(in, scene.primitive_count()), s.build, s.traversal);
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
