#pragma once
/// BIH construction by the global heuristic of Wächter & Keller (2006), and its figures.
#include <cstddef>
#include <iosfwd>
#include <span>

#include "thicket/bih/node.h"
#include "thicket/core/tree_figures.h"

namespace thicket {

/// What the builder does when every object falls on one side of the candidate plane.
enum class BihEmptySide {
    Refine,  ///< halve the candidate box and try again; no node is made (the paper's default)
    Cut,     ///< also make a node with an empty child when that cuts off a quarter of the node
};

struct BihBuildOptions {
    int max_leaf = 4;  ///< a range of at most this many primitives becomes a leaf
    BihEmptySide empty_side = BihEmptySide::Cut;
};

/// Builds a BIH over primitives with the given bounds. Split candidates are the midpoints of the
/// candidate box, which starts as the scene's bounds and is halved at every level whatever the
/// objects' bounds are; objects go left when their box centre lies below the candidate plane,
/// and the node's clip planes are the actual extremes of the two sides.
BihData build_bih(std::span<const Aabb> bounds, const BihBuildOptions& options);

/// Figures of a built BIH. Child boxes are the parent's box clipped by the child's plane, the
/// root's box is the scene's bounds; sah_cost uses kSahTraversalCost and kSahIntersectionCost.
using BihFigures = TreeFigures;
BihFigures bih_figures(const BihData& bih);

/// Checks the structural invariants (indices in range, children after parents, depth bounded,
/// every primitive referenced once); throws Error describing the first violation.
void validate_bih(const BihData& bih, size_t primitive_count);
/// What traversal relies on beyond structure (call after validate_bih): the root box contains
/// every primitive, and each interior node's planes enclose its whole subtree on its axis (left
/// subtree's bounds <= left_max, right subtree's >= right_min), so clipping the ray interval at
/// the planes never cuts off a hit.
void validate_bih_bounds(const BihData& bih, std::span<const Aabb> prim_bounds);

/// Payload I/O for save_accel/load_accel; read_bih validates before returning.
void write_bih(std::ostream& out, const BihData& bih);
BihData read_bih(std::istream& in, size_t primitive_count);

}  // namespace thicket
