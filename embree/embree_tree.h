#pragma once
/// Embree's own builder (rtcBuildBVH) writing `bvh8`'s tree: `bvh8:tree=embree-medium` and
/// `bvh8:tree=embree-high` in the bench, so that bvh8's kernels trace Embree's tree and the gap
/// to Embree splits into the tree's part and the kernel's (issue 43, BENCHMARKS.md).
///
/// The arguments are those of Embree's BVH8Triangle4 scene builders: 8 wide, leaves costed in
/// 4-triangle blocks (sahBlockSize 4), 4 to 28 primitives per leaf, traversal and intersection
/// cost 1, 32 object bins; high adds its spatial splits (primitive array 1.2x the primitives,
/// each cut clipped exactly by the set's clipped_bounds, as Embree clips triangles).
namespace thicket {

/// Installs the builder into bvh8 (bvh8::set_foreign_tree_builder); idempotent.
void install_embree_tree_builder();

}  // namespace thicket
