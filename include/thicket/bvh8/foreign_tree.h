#pragma once
/// `bvh8:tree=embree-medium|embree-high`: the 8-wide tree built by another library's builder
/// (Embree's rtcBuildBVH, the bench's Embree module) and traced by bvh8's own kernels, so that
/// the bench splits the gap to Embree into the tree's part and the kernel's (issue 43). The
/// library does not link Embree: the module installs its builder here when it starts.
#include <span>

#include "thicket/bvh/build.h"
#include "thicket/bvh8/build.h"

namespace thicket::bvh8 {

/// Who builds bvh8's tree.
enum class TreeSource {
    Thicket,       ///< the binary builder of the options, collapsed (collapse())
    EmbreeMedium,  ///< Embree's binned SAH (RTC_BUILD_QUALITY_MEDIUM), 8 wide, 4-triangle blocks
    EmbreeHigh,    ///< the same with Embree's fast spatial splits (RTC_BUILD_QUALITY_HIGH)
};

/// What a foreign builder gets: every primitive's bounds, the exact clip of a primitive to a box
/// (for spatial splits), which builder, and the threads it may use (0: every core).
struct ForeignTreeRequest {
    std::span<const Aabb> prim_bounds;
    ClipFunction clip;
    TreeSource source = TreeSource::EmbreeMedium;
    unsigned threads = 0;
};
/// Builds the tree; throws Error on failure.
using ForeignTreeBuilder = WideTree (*)(const ForeignTreeRequest& request);

/// Installs the builder of the sources other than Thicket (the bench's Embree module does).
void set_foreign_tree_builder(ForeignTreeBuilder builder);
/// The installed builder's tree; throws Error naming the option when none is installed.
WideTree build_foreign_tree(const ForeignTreeRequest& request);

}  // namespace thicket::bvh8
