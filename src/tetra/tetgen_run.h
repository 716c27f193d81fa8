#pragma once
// TetGen run in a child process: its crashes (TetGen 1.5 dereferences null on some
// self-intersecting inputs instead of reporting them), its unbounded run time and its memory
// stay out of the calling process. Private to src/tetra.
#include <cstddef>
#include <string>
#include <vector>

namespace thicket::tetra_detail {

/// A piecewise linear complex: points (xyz), triangles (3 point ids each, marker = its entry in
/// `markers`, > 0) and the 8 corners of the box, given as points 0..7, closed by 6 facets.
struct TetgenInput {
    std::vector<double> points;
    std::vector<int> triangles;
    std::vector<int> markers;
};

/// TetGen's output: points, tetrahedra (4 ids), neighbours (4 ids, -1 on the hull),
/// constrained faces (3 ids) with their markers (-1 on the box).
struct TetgenOutput {
    std::vector<double> points;
    std::vector<int> tets, neighbors, faces, face_markers;
};

struct TetgenResult {
    bool ok = false;
    std::string failure;  ///< why not, when !ok
    TetgenOutput out;
    double ms = 0;
};

/// Runs TetGen with `switches` (the library's command-line letters) on `in` in a child process
/// stopped after `seconds` and limited to `memory_mb` of address space.
TetgenResult run_tetgen(const TetgenInput& in, const std::string& switches, double seconds, size_t memory_mb);

}  // namespace thicket::tetra_detail
