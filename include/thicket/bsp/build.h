#pragma once
/// BSP construction by autopartition: each node's plane is the supporting plane of one of its
/// own triangles (Sung & Shirley, Graphics Gems III), chosen among a sample by a cost; triangles
/// that straddle it are cut into convex fragments. Sets without triangles fall back to
/// axis-aligned planes from the primitives' bounds (a kD-tree with bounds-based assignment).
#include <array>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <span>
#include <vector>

#include "thicket/bsp/node.h"
#include "thicket/core/tree_figures.h"

namespace thicket {

/// How a node's plane is chosen among the sampled candidates.
enum class BspCost {
    /// Surface-area estimate: sum over both sides of (fragments) x (area of the side's cell box
    /// cut down to the bounds of its fragments); straddling fragments count on both sides.
    Sah,
    /// The classic autopartition score: |front - back| + 8 x straddling (fewest splits, balance).
    Balance,
};

struct BspBuildOptions {
    BspCost cost = BspCost::Sah;
    int candidates = 12;      ///< triangles whose planes are tried per node (non-triangle sets: x6 planes)
    int max_leaf = 4;         ///< a node with more fragments is split while some plane separates them
    int max_depth = 48;       ///< deeper nodes become leaves (at most kBspMaxDepth)
    int fragment_budget = 8;  ///< at most fragment_budget x primitives fragments in the whole tree
    /// Where a node's own planes would only peel (the best leaves more than 7/8 of its fragments
    /// on one side, as tangent planes of a curved surface do), also score the axis-aligned
    /// planes through the median of its fragments' box centres.
    bool axis_fallback = true;
};

/// One leaf fragment as the builder left it (tests and diagnostics): the convex polygon, a piece
/// of triangle `prim` (empty for non-triangle sets), and its box (the bounds for those sets).
struct BspFragment {
    uint32_t leaf = 0;
    uint32_t prim = 0;
    std::vector<std::array<double, 3>> polygon;
    Aabb box;
};

/// Builds over triangles. If `fragments` is given, it receives every leaf's fragments.
BspData build_bsp_triangles(std::span<const std::array<Vec3, 3>> triangles, const BspBuildOptions& options,
                            std::vector<BspFragment>* fragments = nullptr);

/// Bounds of the part of primitive `prim` inside `box` (clipped_bounds of the primitive set).
using BspClip = std::function<Aabb(uint32_t prim, const Aabb& box)>;

/// Builds over primitives known only by their bounds, with axis-aligned planes.
BspData build_bsp_boxes(std::span<const Aabb> bounds, const BspClip& clip, const BspBuildOptions& options,
                        std::vector<BspFragment>* fragments = nullptr);

/// Figures of a built tree. The SAH cost uses each node's cell box (the root's box cut by the
/// planes on its path, as a box) relative to the root's, with kSahTraversalCost and
/// kSahIntersectionCost.
using BspFigures = TreeFigures;
BspFigures bsp_figures(const BspData& bsp);

/// Checks the structural invariants (references in range, children after parents, depth
/// bounded, unit planes, every node reachable, leaves tiling the references); throws Error
/// describing the first violation.
void validate_bsp(const BspData& bsp, size_t primitive_count);

/// The BSP's load-time proof: its leaves hold fragments clipped down the planes above them, and no
/// check cheaper than the clipping proves a moved plane or a lost fragment harmless, so a loaded
/// tree must be the very tree the (deterministic) builder makes for the scene and spec. Throws
/// Error naming the first byte at which `saved`'s payload differs from `rebuilt`'s.
void prove_bsp_rebuilt(const BspData& saved, const BspData& rebuilt);

/// Payload I/O for save_accel/load_accel; read_bsp validates before returning.
void write_bsp(std::ostream& out, const BspData& bsp);
BspData read_bsp(std::istream& in, size_t primitive_count);

/// The boxes around the parts of `box` behind and in front of `plane` (closed half-spaces;
/// empty where nothing of the box is). Rounded to nearest: for cost estimates and figures.
void bsp_cut_box(const Aabb& box, const BspPlane& plane, Aabb& back, Aabb& front);
Aabb bsp_cut_box(const Aabb& box, const BspPlane& plane, bool front);

}  // namespace thicket
