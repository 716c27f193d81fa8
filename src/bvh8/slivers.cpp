// The degenerate-triangle tree: built after the main tree from the slivers its packing set
// aside (or that a loaded tree's proof found), and searched by closest points only.
#include "thicket/bvh8/slivers.h"

#include <algorithm>

#include "thicket/prims/triangles.h"

namespace thicket::bvh8 {

template <class Tris>
size_t count_degenerate(const Tris& tris) {
    size_t count = 0;
    for (uint32_t i = 0; i < tris.size(); ++i) {
        const auto v = tris.triangle(i);
        count += Tris::degenerate({v[0], v[1], v[2]}) ? 1 : 0;
    }
    return count;
}

template <class Tris>
SliverTree build_sliver_tree(const Tris& tris, std::vector<uint32_t> slivers, const BvhBuildOptions& binary,
                             uint32_t merge_below) {
    std::sort(slivers.begin(), slivers.end());
    slivers.erase(std::unique(slivers.begin(), slivers.end()), slivers.end());
    SliverTree out;
    if (slivers.empty()) return out;
    std::vector<Aabb> bounds;
    std::vector<Vec3> centroids;
    primitive_boxes(
        uint32_t(slivers.size()), binary.threads, bounds, centroids,
        [&](uint32_t i) { return tris.bounds(slivers[i]); }, [&](uint32_t i) { return tris.centroid(slivers[i]); });
    BvhBuildOptions object_partition = binary;
    if (object_partition.builder == BvhBuilder::Sbvh) object_partition.builder = BvhBuilder::BinnedSah;
    const BvhData tree = build_bvh({bounds, centroids}, object_partition);
    std::vector<uint32_t> ids;
    BlockPacking packing;  // no sliver list: every triangle here is kept
    out.tree = collapse(
        tree,
        [&](uint32_t first, uint32_t count) {
            ids.clear();
            for (uint32_t k = 0; k < count; ++k) ids.push_back(slivers[tree.prim_indices[first + k]]);
            return pack_blocks(out.blocks, tris, ids.data(), count, packing);
        },
        merge_below);
    validate_tree(out.tree, out.blocks.size());
    return out;
}

template size_t count_degenerate(const Triangles<TriangleTest::Moller>&);
template size_t count_degenerate(const Triangles<TriangleTest::Watertight>&);
template SliverTree build_sliver_tree(const Triangles<TriangleTest::Moller>&, std::vector<uint32_t>,
                                      const BvhBuildOptions&, uint32_t);
template SliverTree build_sliver_tree(const Triangles<TriangleTest::Watertight>&, std::vector<uint32_t>,
                                      const BvhBuildOptions&, uint32_t);

}  // namespace thicket::bvh8
