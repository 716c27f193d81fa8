#pragma once
/// A box cut into res[0] x res[1] x res[2] equal cells: cell geometry, linear cell indices, and
/// the index range a box covers. Shared by the uniform grid, the two-level grid's top level and
/// each of its sub-grids.
#include <array>
#include <cmath>
#include <cstdint>

#include "thicket/core/aabb.h"
#include "thicket/grid/resolution.h"

namespace thicket {

/// Cell index range [lo, hi] per axis, inclusive.
struct CellRange {
    std::array<uint32_t, 3> lo{}, hi{};
    bool single() const { return lo == hi; }
};

struct GridFrame {
    Vec3 min, max;      ///< the box
    Vec3 cell;          ///< cell size per axis (0 on a flat axis)
    Vec3 inv_cell;      ///< cells per unit length; 0 where the axis has one cell, so its index is always 0
    Vec3 eps;           ///< how far beyond a cell a primitive still counts as overlapping it (see make)
    std::array<uint32_t, 3> res{1, 1, 1};
    std::array<uint32_t, 3> stride{1, 1, 1};  ///< linear index = x*stride[0] + y*stride[1] + z*stride[2]

    /// Fraction of a cell by which cells are widened when primitives are assigned. It makes every
    /// primitive that touches a cell's closed box (shared faces, edges and corners included) count
    /// for that cell despite rounding in the index and plane computations, so a ray that the DDA
    /// walks through a neighbouring cell near a corner still meets it.
    static constexpr float kCellSlack = 1.0f / 64.0f;

    static GridFrame make(const Aabb& box, const GridResolution& r) {
        GridFrame f;
        f.min = box.min;
        f.max = box.max;
        for (int a = 0; a < 3; ++a) {
            const double extent = double(box.max[a]) - double(box.min[a]);
            f.res[a] = r.n[a];
            f.cell[a] = float(extent / r.n[a]);
            f.inv_cell[a] = r.n[a] > 1 && extent > 0.0 ? float(r.n[a] / extent) : 0.0f;
            // Rounding of coordinates of this magnitude, far below a cell for any sane grid.
            const float magnitude = std::max(std::fabs(box.min[a]), std::fabs(box.max[a]));
            f.eps[a] = f.cell[a] * kCellSlack + magnitude * 0x1p-20f;
            if (!std::isfinite(f.eps[a])) f.eps[a] = 0.0f;
        }
        f.stride = {1, f.res[0], f.res[0] * f.res[1]};
        return f;
    }

    uint32_t cells() const { return res[0] * res[1] * res[2]; }
    uint32_t index(uint32_t x, uint32_t y, uint32_t z) const { return x * stride[0] + y * stride[1] + z * stride[2]; }

    /// Lower plane of cell i on axis a (i == res[a] gives the upper plane of the last cell).
    float plane(int a, uint32_t i) const { return min[a] + float(i) * cell[a]; }

    /// Calls visit(cell, i) for every cell, cell = {x, y, z} and i = index(x, y, z), in the order of
    /// i (x fastest): the one walk over a frame's cells.
    template <class Visit>
    void for_each_cell(Visit&& visit) const {
        uint32_t cell[3];
        for (cell[2] = 0; cell[2] < res[2]; ++cell[2])
            for (cell[1] = 0; cell[1] < res[1]; ++cell[1])
                for (cell[0] = 0; cell[0] < res[0]; ++cell[0]) visit(cell, index(cell[0], cell[1], cell[2]));
    }

    /// The closed box of cell (x, y, z).
    Aabb cell_box(uint32_t x, uint32_t y, uint32_t z) const {
        const uint32_t c[3] = {x, y, z};
        return cell_box(c);
    }

    /// The closed box of cell c = {x, y, z}.
    Aabb cell_box(const uint32_t c[3]) const {
        Aabb b;
        for (int a = 0; a < 3; ++a) {
            b.min[a] = plane(a, c[a]);
            b.max[a] = res[a] == 1 || c[a] + 1 == res[a] ? max[a] : plane(a, c[a] + 1);
        }
        return b;
    }

    /// Cell index on axis a of coordinate x, clamped into [0, res[a]) (NaN goes to 0).
    uint32_t clamp_index(int a, double x) const {
        const double f = std::floor((x - double(min[a])) * double(inv_cell[a]));
        if (!(f >= 0.0)) return 0;
        if (!(f < double(res[a]))) return res[a] - 1;
        return uint32_t(f);
    }

    /// Cells whose boxes, widened by eps, overlap box b; false if b does not come within eps of
    /// the frame at all.
    bool range(const Aabb& b, CellRange& r) const {
        for (int a = 0; a < 3; ++a) {
            if (b.min[a] - eps[a] > max[a] || b.max[a] + eps[a] < min[a]) return false;
            r.lo[a] = clamp_index(a, double(b.min[a]) - double(eps[a]));
            r.hi[a] = clamp_index(a, double(b.max[a]) + double(eps[a]));
        }
        return true;
    }

    /// The slab of cells i on axis a, widened by eps on that axis, spanning `around` elsewhere.
    Aabb slab(int a, uint32_t i, const Aabb& around) const {
        Aabb s = around;
        s.min[a] = plane(a, i) - eps[a];
        s.max[a] = (res[a] == 1 || i + 1 == res[a] ? max[a] : plane(a, i + 1)) + eps[a];
        return s;
    }

    /// The frame's box widened by eps.
    Aabb widened() const { return {min - eps, max + eps}; }
};

}  // namespace thicket
