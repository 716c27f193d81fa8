#pragma once
/// OBB tree construction: on the topology of a BVH (Vitsas et al. 2023 transform a BVH the same
/// way), every node's box is refitted as an oriented box around the points of its primitives.
#include <cstddef>
#include <iosfwd>
#include <span>
#include <vector>

#include "thicket/bvh/node.h"
#include "thicket/core/aabb.h"
#include "thicket/core/tree_figures.h"
#include "thicket/obb/node.h"

namespace thicket {

/// How each node's orientation is chosen.
enum class ObbFit {
    Pca,   ///< principal axes of the node's points, or the world axes when those give less area
    Axes,  ///< the world axes: the BVH's own boxes (a baseline that must match the bvh's visits)
};

/// The points each primitive is fitted by: those of primitive i are
/// points[offsets[i] .. offsets[i+1]) (a triangle's three vertices, another shape's box corners).
struct ObbPoints {
    std::vector<Vec3> points;
    std::vector<uint32_t> offsets;  ///< one more entry than there are primitives
};

/// The oriented box of every node of `bvh` (same topology, renumbered root first, children in
/// pairs) around the points of the primitives below it; `scale` (the scene's largest coordinate
/// magnitude or extent) sets the absolute margin each box grows by so rounding in the ray's
/// change of frame can never cull a hit. Fits nodes on up to `threads` threads (0: every core).
ObbData build_obb(const BvhData& bvh, const ObbPoints& points, ObbFit fit, float scale, unsigned threads);

/// After the primitives moved (same topology, `points` as build_obb takes them, `scale` the moved
/// scene's): every node keeps its axes and gets the centre and extents that enclose its points
/// again, with the build's margins. On up to `threads` threads (0: every core).
void refit_obb(ObbData& obb, const ObbPoints& points, float scale, unsigned threads);

/// Half the surface area of a node's box (the sum of the products of its full extents' pairs),
/// the measure Aabb::half_area() gives an axis-aligned box.
float obb_area(const ObbNode& node);

/// Figures of a built tree with OBB surface areas, relative to `reference_area` (pass the scene
/// AABB's area so the SAH cost compares with the bvh's, whose root is that box).
TreeFigures obb_figures(const ObbData& obb, float reference_area);

/// Checks the structural invariants (indices in range, children after parents, depth bounded,
/// every primitive referenced once, finite boxes with orthonormal axes); throws Error
/// describing the first violation.
void validate_obb(const ObbData& obb, size_t primitive_count);
/// What traversal relies on beyond structure (call after validate_obb): every node's box
/// encloses every point (`points`, as build_obb was given them) of every primitive below it,
/// with the allowance src/obb/validate_bounds.cpp derives from `scale` (the builder's); throws
/// Error naming the node and the primitive. Never refuses a tree build_obb made.
void validate_obb_bounds(const ObbData& obb, const ObbPoints& points, float scale);

/// Payload I/O for save_accel/load_accel; read_obb validates before returning.
void write_obb(std::ostream& out, const ObbData& obb);
ObbData read_obb(std::istream& in, size_t primitive_count);

}  // namespace thicket
