#pragma once
/// BVH construction: a top-down skeleton shared by every builder, each builder choosing splits.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "thicket/bvh/node.h"
#include "thicket/core/tree_figures.h"
#include "thicket/core/huge_pages.h"
#include "thicket/util/parallel.h"

namespace thicket {

/// Nodes of at most this many primitives are split on block boundaries when
/// BvhBuildOptions::sah_block is above 1 (block_builder.cpp): their leaves then waste fewer than
/// sah_block slots in all. Larger nodes keep the builder's own split choice. 16 measured best of
/// 0, 8, 16, 32 and 64 (BENCHMARKS.md, "Block split bound").
inline constexpr uint32_t kBlockPackMax = 16;

/// Nodes this big or bigger are the "top" of a build: bounded, binned and partitioned by all the
/// build's threads together; smaller nodes root subtrees built one per thread.
inline constexpr uint32_t kParallelNodeSize = 16384;

/// Bounds and centroids of primitives 0..count-1 (get_bounds(i), get_centroid(i)) on up to
/// `threads` threads; the builders' input for any primitive set whose queries are thread-safe.
/// bounds[i] is stored before get_centroid(i) is called, so a centroid may be read from it.
template <class GetBounds, class GetCentroid>
void primitive_boxes(uint32_t count, unsigned threads, std::vector<Aabb>& bounds, std::vector<Vec3>& centroids,
                     GetBounds&& get_bounds, GetCentroid&& get_centroid) {
    reserve_huge(bounds, count);
    reserve_huge(centroids, count);
    bounds.resize(count);
    centroids.resize(count);
    parallel_for(count, kParallelNodeSize, threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            bounds[i] = get_bounds(uint32_t(i));
            centroids[i] = get_centroid(uint32_t(i));
        }
    });
}

enum class BvhBuilder { Midpoint, BinnedSah, SweepSah, Lbvh, Sbvh, Ploc };
enum class BvhOptimize { None, Reinsertion };

struct BvhBuildOptions {
    BvhBuilder builder = BvhBuilder::BinnedSah;
    int bins = 8;      ///< binned-sah: bins per axis (Wald 2007)
    int max_leaf = 8;  ///< a node with more primitives is always split
    /// Primitives the SAH tests as one: a leaf of n costs ceil(n / sah_block) intersections. 1
    /// (the lecture's count); 4 for leaves stored as 4-triangle blocks (bvh8), where a leaf of 5
    /// costs as much as one of 8. Above 1, binned-sah and sweep-sah also split nodes of at most
    /// kBlockPackMax primitives only where a multiple of sah_block goes left, so such a node's
    /// leaves fill all their blocks but one (sbvh: its object splits; spatial ones stay free).
    uint32_t sah_block = 1;
    /// Threads the build may use (0: every core). Never changes the result: the tree is the same
    /// byte for byte on any number of threads.
    unsigned threads = 0;
    BvhOptimize optimize = BvhOptimize::None;  ///< applied to the built tree (optimize_reinsertion)
    int optimize_passes = 3;                   ///< the optimizer's budget: passes at most
    /// sbvh: spatial splits are tried only where the best object split's children overlap by more
    /// than this fraction of the root's surface area (Stich et al. 2009's alpha).
    double sbvh_alpha = 1e-3;
    /// sbvh: at most (1 + budget) * N references in all (each spatial split adds the references it
    /// cuts in two); 0 makes no spatial split.
    double sbvh_budget = 0.3;
    /// ploc: clusters searched on each side of a cluster for its nearest neighbour (build_ploc).
    uint32_t ploc_radius = 16;
};

/// Bounds of the part of primitive `prim` inside `box` (clipped_bounds() of the primitive set).
using ClipFunction = std::function<Aabb(uint32_t prim, const Aabb& box)>;

/// What builders see of the primitives: bounds and centroids, and for spatial splits (sbvh) the
/// bounds of a primitive's part inside a box.
struct BuildPrimitives {
    std::span<const Aabb> bounds;
    std::span<const Vec3> centroids;
    /// Empty: bounds intersected with the box (conservative; spatial splits then cut boxes, not
    /// primitives).
    ClipFunction clip = {};
};

/// Most references a BVH may hold per primitive (a loaded file claiming more is refused): sbvh's
/// budget is at most kMaxReferencesPerPrimitive - 1.
inline constexpr uint32_t kMaxReferencesPerPrimitive = 5;

/// Builds a BVH over the primitives. Leaves are made when the SAH says splitting costs more
/// (kSahTraversalCost, kSahIntersectionCost) and the node holds at most max_leaf primitives.
/// Nodes of kParallelNodeSize primitives or more are split with their loops spread over
/// options.threads; smaller ones root subtrees built as independent tasks and laid out after the
/// top nodes in depth-first order of their roots, so the layout never depends on the threads.
BvhData build_bvh(const BuildPrimitives& prims, const BvhBuildOptions& options);

/// "R (x.xx per primitive)": the `references` figure of the stats of structures built on the
/// binary BVH (above 1.00 per primitive only with spatial splits, builder=sbvh).
std::string reference_figure(size_t references, size_t primitives);

/// Figures of a built BVH (node boxes as stored).
using BvhFigures = TreeFigures;
BvhFigures bvh_figures(const BvhData& bvh);

/// Checks the structural invariants (indices in range, children after parents, depth bounded,
/// leaves partitioning the index array, every primitive referenced at least once and at most
/// kMaxReferencesPerPrimitive times per primitive on average); throws Error describing the first
/// violation. Only a spatial-split build (sbvh) references a primitive more than once.
void validate_bvh(const BvhData& bvh, size_t primitive_count);
/// What traversal relies on beyond structure (call after validate_bvh): every interior box
/// contains its children's, every child-order byte names real axes, and every primitive is
/// covered by the leaves listing it: a primitive listed once lies in its leaf's box; one listed
/// in several leaves (spatial splits) has every part of it in one of their boxes, proved by
/// cutting it along those boxes' faces with `clip` (empty: bounds intersected with the box).
/// With these, culling a node whose box the ray misses never loses a hit.
void validate_bvh_bounds(const BvhData& bvh, std::span<const Aabb> prim_bounds, const ClipFunction& clip = {});

/// Payload I/O for save_accel/load_accel; read_bvh validates before returning.
void write_bvh(std::ostream& out, const BvhData& bvh);
BvhData read_bvh(std::istream& in, size_t primitive_count);

}  // namespace thicket
