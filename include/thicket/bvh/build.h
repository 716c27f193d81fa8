#pragma once
/// BVH construction: a top-down skeleton shared by every builder, each builder choosing splits.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "thicket/bvh/node.h"
#include "thicket/core/tree_figures.h"
#include "thicket/util/parallel.h"

namespace thicket {

/// Nodes this big or bigger are the "top" of a build: bounded, binned and partitioned by all the
/// build's threads together; smaller nodes root subtrees built one per thread.
inline constexpr uint32_t kParallelNodeSize = 16384;

/// Bounds and centroids of primitives 0..count-1 (get_bounds(i), get_centroid(i)) on up to
/// `threads` threads; the builders' input for any primitive set whose queries are thread-safe.
template <class GetBounds, class GetCentroid>
void primitive_boxes(uint32_t count, unsigned threads, std::vector<Aabb>& bounds, std::vector<Vec3>& centroids,
                     GetBounds&& get_bounds, GetCentroid&& get_centroid) {
    bounds.resize(count);
    centroids.resize(count);
    parallel_for(count, kParallelNodeSize, threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            bounds[i] = get_bounds(uint32_t(i));
            centroids[i] = get_centroid(uint32_t(i));
        }
    });
}

enum class BvhBuilder { Midpoint, BinnedSah, SweepSah, Lbvh };
enum class BvhOptimize { None, Reinsertion };

struct BvhBuildOptions {
    BvhBuilder builder = BvhBuilder::BinnedSah;
    int bins = 8;      ///< binned-sah: bins per axis (Wald 2007)
    int max_leaf = 8;  ///< a node with more primitives is always split
    /// Threads the build may use (0: every core). Never changes the result: the tree is the same
    /// byte for byte on any number of threads.
    unsigned threads = 0;
    BvhOptimize optimize = BvhOptimize::None;  ///< applied to the built tree (optimize_reinsertion)
    int optimize_passes = 3;                   ///< the optimizer's budget: passes at most
};

/// What builders see of the primitives: bounds and centroids, nothing else.
struct BuildPrimitives {
    std::span<const Aabb> bounds;
    std::span<const Vec3> centroids;
};

/// Builds a BVH over the primitives. Leaves are made when the SAH says splitting costs more
/// (kSahTraversalCost, kSahIntersectionCost) and the node holds at most max_leaf primitives.
/// Nodes of kParallelNodeSize primitives or more are split with their loops spread over
/// options.threads; smaller ones root subtrees built as independent tasks and laid out after the
/// top nodes in depth-first order of their roots, so the layout never depends on the threads.
BvhData build_bvh(const BuildPrimitives& prims, const BvhBuildOptions& options);

/// Figures of a built BVH (node boxes as stored).
using BvhFigures = TreeFigures;
BvhFigures bvh_figures(const BvhData& bvh);

/// Checks the structural invariants (indices in range, children after parents, depth bounded,
/// every primitive referenced once); throws Error describing the first violation.
void validate_bvh(const BvhData& bvh, size_t primitive_count);
/// What traversal relies on beyond structure (call after validate_bvh): every leaf box contains
/// its primitives' bounds, every interior box its children's, every child-order byte names real
/// axes. With these, culling a node whose box the ray misses never loses a hit.
void validate_bvh_bounds(const BvhData& bvh, std::span<const Aabb> prim_bounds);

/// Payload I/O for save_accel/load_accel; read_bvh validates before returning.
void write_bvh(std::ostream& out, const BvhData& bvh);
BvhData read_bvh(std::istream& in, size_t primitive_count);

}  // namespace thicket
