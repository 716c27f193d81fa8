#include "accel/dispatch.h"
#include "thicket/octree/octree.h"

namespace thicket {

namespace {

constexpr Choice<OctreeTraversal> kTraversals[] = {
    {"parametric", OctreeTraversal::Parametric},
    {"restart", OctreeTraversal::Restart},
};

using OctreeSettings = BuildAndTraversal<OctreeBuildOptions, OctreeTraversal, OctreeTraversal::Parametric>;

}  // namespace

void register_octree(std::vector<AccelInfo>& registry) {
    using B = OctreeBuildOptions;
    const OptionFields<OctreeSettings> fields = join_fields(
        fields_in(&OctreeSettings::build,
                  {int_field("leaf-size", "a cell holding more primitives is split into its eight octants",
                             &B::leaf_size, 1, 255),
                   int_field("max-depth", "deepest level (the root is level 0)", &B::max_depth, 0,
                             long(kOctreeMaxDepth))}),
        OptionFields<OctreeSettings>{choice_field(
            "traversal",
            "parametric (Revelles, Urena & Lastra 2000: plane distances, first-node and next-node rules) or "
            "restart (the lecture: locate the leaf at the current distance from the root, test it, continue at "
            "its exit)",
            &OctreeSettings::traversal, kTraversals)});
    AccelInfo info = accel_info({.name = "octree",
                                 .partitioning = Partitioning::Space,
                                 .summary = "adaptive octree (Glassner 1984): cubic cells split in eight, parametric "
                                            "(Revelles et al. 2000) or restart traversal",
                                 .variants = {"octree", "octree:traversal=restart", "octree:leaf-size=2,max-depth=16",
                                              "octree:traversal=restart,leaf-size=1,max-depth=4,isect=watertight"}},
                                fields);
    info.build = [fields](const Scene& scene, const AccelSpec& spec) {
        const OctreeSettings s = read_settings(fields, spec);
        return make_structure<Octree>(scene, spec, s.build, s.traversal);
    };
    info.load = [fields](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        return make_structure<Octree>(scene, spec, read_octree(in, scene.primitive_count()),
                                      read_settings(fields, spec).traversal);
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
