#include "accel/dispatch.h"
#include "thicket/octree/octree.h"

namespace thicket {

namespace {

constexpr Choice<OctreeTraversal> kTraversals[] = {
    {"parametric", OctreeTraversal::Parametric},
    {"restart", OctreeTraversal::Restart},
};

}  // namespace

void register_octree(std::vector<AccelInfo>& registry) {
    AccelInfo info;
    info.name = "octree";
    info.partitioning = Partitioning::Space;
    info.summary = "adaptive octree (Glassner 1984): cubic cells split in eight, parametric (Revelles et al. 2000) "
                   "or restart traversal";
    info.options = {
        {"leaf-size", "a cell holding more primitives is split into its eight octants", "8", {}, 1, 255},
        {"max-depth", "deepest level (the root is level 0)", "10", {}, 0, long(kOctreeMaxDepth)},
        choice_option("traversal",
                      "parametric (Revelles, Urena & Lastra 2000: plane distances, first-node and next-node rules) "
                      "or restart (the lecture: locate the leaf at the current distance from the root, test it, "
                      "continue at its exit)",
                      OctreeTraversal::Parametric, kTraversals),
    };
    info.variants = {"octree", "octree:traversal=restart", "octree:leaf-size=2,max-depth=16",
                     "octree:traversal=restart,leaf-size=1,max-depth=4,isect=watertight"};
    info.build = [](const Scene& scene, const AccelSpec& spec) {
        OctreeBuildOptions o;
        o.leaf_size = int(spec.get_int("leaf-size"));
        o.max_depth = int(spec.get_int("max-depth"));
        return make_structure<Octree>(scene, spec, o, spec.choice("traversal", kTraversals));
    };
    info.load = [](std::istream& in, const Scene& scene, const AccelSpec& spec) {
        return make_structure<Octree>(scene, spec, read_octree(in, scene.primitive_count()),
                                      spec.choice("traversal", kTraversals));
    };
    registry.push_back(std::move(info));
}

}  // namespace thicket
