#pragma once
/// How many cells a grid gets: the density rule n_axis = e_axis * (lambda * N / V)^(1/3) (Cleary &
/// Wyvill 1988; lambda = cells per primitive), or an explicit count along the longest axis, and
/// the caps that keep absurd requests from allocating terabytes.
#include <array>
#include <cstdint>
#include <string>

#include "thicket/core/vec3.h"

namespace thicket {

/// Most cells one grid (or all sub-grids of a two-level grid together) may have: 2^26, i.e.
/// 256 MiB of cell offsets. Automatic resolutions are scaled down to fit; explicit ones that do
/// not fit are an Error.
inline constexpr uint64_t kMaxGridCells = uint64_t(1) << 26;
/// Most primitive references (cell -> primitive entries) a grid may hold: 2^28 (1 GiB).
inline constexpr uint64_t kMaxGridReferences = uint64_t(1) << 28;

/// Cells per axis.
struct GridResolution {
    std::array<uint32_t, 3> n{1, 1, 1};
    uint64_t cells() const { return uint64_t(n[0]) * n[1] * n[2]; }
    std::string str() const;  ///< "nx x ny x nz"
};

/// Cells for a box of `extent` that should hold about `cells_wanted` cells, proportional to the
/// box's aspect ratio: axes of zero extent (or too thin for one cell) get one cell and the others
/// share the budget. At most `max_per_axis` per axis and `max_cells` in all (scaled down to fit);
/// a non-finite extent gets a single cell (the grid then tests everything, like brute force).
GridResolution density_resolution(Vec3 extent, double cells_wanted, uint32_t max_per_axis, uint64_t max_cells);

/// `cells_longest` cells along the longest axis, the other axes proportional (at least 1).
/// Throws Error naming `what` (e.g. "grid: res=5000") when that exceeds kMaxGridCells.
GridResolution longest_axis_resolution(Vec3 extent, uint32_t cells_longest, const std::string& what);

}  // namespace thicket
