#pragma once
/// The tetrahedral mesh the `tetra` structure walks (Lagae & Dutré 2008): TetGen's constrained
/// Delaunay tetrahedralization of the scene's triangles inside a box, with, per vertex, the scene
/// triangles whose pieces (constrained faces) touch it, and a coarse grid of walk start points.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "thicket/bvh/node.h"
#include "thicket/core/vec3.h"

namespace thicket {

inline constexpr uint32_t kNoTet = 0xFFFFFFFFu;

struct TetraMesh {
    std::vector<Vec3d> points;           ///< TetGen's output vertices (input, box corners, Steiner points)
    std::vector<uint32_t> tets;       ///< 4 vertex ids per tetrahedron; face k is opposite vertex k
    std::vector<uint32_t> neighbors;  ///< 4 per tetrahedron: the one across face k, kNoTet on the hull
    std::vector<uint32_t> face_tris;  ///< 4 per tetrahedron: the scene triangle face k is part of, or kNoTet
    /// Scene triangles at each vertex: those of vertex v are tris[offsets[v] .. offsets[v+1]).
    std::vector<uint32_t> vertex_offsets, vertex_tris;
    Vec3d box_min, box_max;              ///< the box the tetrahedra fill
    uint32_t grid_res = 0;            ///< start grid: grid_res^3 cells over the box
    std::vector<uint32_t> grid_start; ///< per cell, a tetrahedron near its centre

    size_t tet_count() const { return tets.size() / 4; }
    size_t bytes() const {
        return points.size() * sizeof(Vec3d) + (tets.size() + neighbors.size() + face_tris.size() + vertex_offsets.size() +
                                             vertex_tris.size() + grid_start.size()) * sizeof(uint32_t);
    }
};

/// What the build did, for the figures and for a reader wondering why a scene is not walked.
struct TetraReport {
    uint32_t input_triangles = 0;    ///< triangles of the scene
    uint32_t meshed_triangles = 0;   ///< of those, constrained faces of the tetrahedralization
    uint32_t steiner_points = 0;     ///< vertices TetGen added beyond the input and the box corners
    uint32_t tetgen_runs = 0;        ///< TetGen runs (a refused scene is retried once without what it refused)
    double tetgen_ms = 0;            ///< wall time of the TetGen runs
    std::string outcome;             ///< "" when every triangle went in, else why some or all did not
};

/// The whole structure: the mesh, the primitives it does not hold (shapes, degenerate,
/// duplicate, self-intersecting or otherwise refused triangles) and a BVH over those (its
/// indices are positions in `fallback`).
struct TetraData {
    TetraMesh mesh;
    std::vector<uint32_t> fallback;
    BvhData fallback_bvh;
    TetraReport report;
};

}  // namespace thicket
