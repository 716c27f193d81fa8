#pragma once
/// Building the `tetra` structure: scene triangles cleaned, tetrahedralized by TetGen in a child
/// process under a time and memory bound, refused triangles kept in a fallback BVH.
#include <array>
#include <cstddef>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/tetra/mesh.h"

namespace thicket {

struct TetraBuildOptions {
    double time_limit_s = 60;            ///< each TetGen run is stopped past this (then: fallback)
    size_t memory_limit_mb = 4096;       ///< address space of the TetGen process
    size_t max_triangles = 200000;       ///< larger scenes are not handed to TetGen at all
    bool preserve_surface = false;       ///< TetGen -Y: no Steiner points on the triangles
    unsigned threads = 0;                ///< the fallback BVH's build threads
};

/// The scene as the build sees it: primitive i is a triangle iff is_triangle[i], with vertices
/// triangle(i); every other primitive has only its box bounds(i).
struct TetraInput {
    size_t count = 0;
    std::function<bool(uint32_t)> is_triangle;
    std::function<std::array<Vec3, 3>(uint32_t)> triangle;
    std::function<Aabb(uint32_t)> bounds;
};

/// Tetrahedralizes what TetGen accepts and keeps the rest in the fallback; never throws for the
/// scene's content (only for an internal inconsistency), whatever TetGen does.
TetraData build_tetra(const TetraInput& input, const TetraBuildOptions& options);

/// Checks every index and count (tetrahedra, neighbours, incidence lists, start grid, fallback);
/// throws Error naming the first violation.
void validate_tetra(const TetraData& data, size_t primitive_count);
/// What the walk relies on beyond structure (call after validate_tetra): the tetrahedra tile
/// the box once, every meshed triangle is covered by the faces that carry it (and listed at
/// their vertices), the fallback BVH's boxes contain their primitives. Proofs and tolerances in
/// src/tetra/validate_geometry.cpp; throws Error naming what is wrong. Never refuses a structure
/// build_tetra made from the same input.
void validate_tetra_geometry(const TetraData& data, const TetraInput& input);

/// Payload I/O for save_accel/load_accel; read_tetra validates before returning.
void write_tetra(std::ostream& out, const TetraData& data);
TetraData read_tetra(std::istream& in, size_t primitive_count);

}  // namespace thicket
