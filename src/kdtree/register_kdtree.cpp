#include "accel/dispatch.h"
#include "thicket/kdtree/kdtree.h"

namespace thicket {

namespace {

constexpr Choice<KdBuilder> kBuilders[] = {{"sah", KdBuilder::Sah}, {"median", KdBuilder::Median}};
constexpr Choice<KdTraversal> kTraversals[] = {{"stack", KdTraversal::Stack}, {"restart", KdTraversal::Restart}};

KdBuildOptions build_options(const AccelSpec& spec) {
    KdBuildOptions o;
    o.builder = spec.choice("builder", kBuilders);
    return o;
}

KdTraversal traversal_option(const AccelSpec& spec) { return spec.choice("traversal", kTraversals); }

}  // namespace

void register_kdtree(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "kdtree";
    info.partitioning = Partitioning::Space;
    info.summary = "SAH kD-tree (Wald & Havran 2006, O(N log N), perfect splits): 8-byte nodes, mailboxing";
    info.options = {
        choice_option("builder",
                      "sah: events sorted once, SAH sweep (K_T = 1, K_I = 1.5, empty-space bonus 0.8), perfect "
                      "splits, O(N log N); median: middle of the voxel's longest axis, the same SAH decides when "
                      "to stop",
                      KdBuilder::Sah, kBuilders),
        choice_option("traversal",
                      "stack: near/far with a stack (Havran's TA_rec_B); restart: kd-restart, no stack (Foley & "
                      "Sugerman 2005)",
                      KdTraversal::Stack, kTraversals),
    };
    // Every option value in three variants: the default, restart on the same tree, and the other
    // builder with the other triangle test.
    info.variants = {"kdtree:builder=sah,traversal=stack", "kdtree:builder=sah,traversal=restart",
                     "kdtree:builder=median,traversal=stack,isect=watertight"};

    info.build = [](const Scene& scene, const AccelSpec& spec) {
        return make_structure<KdTree>(scene, spec, build_options(spec), traversal_option(spec));
    };
    info.load = [](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        return make_structure<KdTree>(scene, spec, read_kdtree(in, scene.primitive_count()), build_options(spec),
                                      traversal_option(spec));
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
