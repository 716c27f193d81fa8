#pragma once
/// Building cell lists: which cells each primitive overlaps, then count, prefix sum and fill.
/// A primitive goes into every cell of the frame that it touches, cells widened by the frame's
/// eps. With GridAssign::Clip the test is exact for triangles and for primitive sets that can
/// clip themselves to a box (clipped_bounds): the primitive is clipped to each slab of cells
/// along x it spans, the part in a slab to each row along y, and the part in a row covers exactly
/// the z cells of its bounds (it is convex and connected). That costs one clip per slab and row,
/// not per cell. Triangles are clipped incrementally in float (the row clips start from the slab's
/// polygon; rounding there is far below eps); other sets call clipped_bounds. Sets without a clip
/// hook, and GridAssign::Bounds, use the primitive's bounding box.
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/grid/cells.h"
#include "thicket/grid/frame.h"
#include "thicket/prims/primitive_set.h"

namespace thicket {

enum class GridAssign { Bounds, Clip };

/// Scratch space reused across calls (a two-level build makes one call per top cell).
struct AssignScratch {
    std::vector<uint32_t> cells;   ///< cells of each primitive, primitive after primitive
    std::vector<uint32_t> first;   ///< where each primitive's cells begin in `cells`
    std::vector<uint32_t> cursor;  ///< per cell: count, then fill position
};

namespace grid_detail {

/// A convex polygon: a triangle clipped by at most four planes has at most seven vertices.
struct ClipPolygon {
    Vec3 v[8];
    int n = 0;

    Aabb bounds() const {
        Aabb b;
        for (int i = 0; i < n; ++i) b.grow(v[i]);
        return b;
    }
};

/// The part of `in` with lo <= p[axis] <= hi (Sutherland-Hodgman against the two planes).
inline ClipPolygon clip_to_slab(const ClipPolygon& in, int axis, float lo, float hi) {
    ClipPolygon tmp, out;
    auto clip = [axis](const ClipPolygon& src, ClipPolygon& dst, float plane, bool keep_above) {
        dst.n = 0;
        for (int i = 0; i < src.n; ++i) {
            const Vec3& a = src.v[i];
            const Vec3& b = src.v[i + 1 == src.n ? 0 : i + 1];
            const bool ain = keep_above ? a[axis] >= plane : a[axis] <= plane;
            const bool bin = keep_above ? b[axis] >= plane : b[axis] <= plane;
            if (ain) dst.v[dst.n++] = a;
            if (ain != bin) {
                const float s = (plane - a[axis]) / (b[axis] - a[axis]);
                Vec3 q = a + (b - a) * s;
                q[axis] = plane;  // exactly on the plane, whatever the rounding
                dst.v[dst.n++] = q;
            }
        }
    };
    clip(in, tmp, lo, true);
    clip(tmp, out, hi, false);
    return out;
}

/// Appends the cells of `f` that triangle (a, b, c) overlaps (cells widened by eps) within the
/// candidate range r of its bounds.
inline void triangle_cells(const std::array<Vec3, 3>& tri, const GridFrame& f, const CellRange& r,
                           std::vector<uint32_t>& out) {
    ClipPolygon poly;
    poly.v[0] = tri[0], poly.v[1] = tri[1], poly.v[2] = tri[2], poly.n = 3;
    for (uint32_t x = r.lo[0]; x <= r.hi[0]; ++x) {
        const Aabb sb = f.slab(0, x, Aabb{});
        const ClipPolygon in_slab = clip_to_slab(poly, 0, sb.min.x, sb.max.x);
        CellRange rs;
        if (in_slab.n == 0 || !f.range(in_slab.bounds(), rs)) continue;
        for (uint32_t y = std::max(rs.lo[1], r.lo[1]); y <= std::min(rs.hi[1], r.hi[1]); ++y) {
            const Aabb rb = f.slab(1, y, Aabb{});
            const ClipPolygon in_row = clip_to_slab(in_slab, 1, rb.min.y, rb.max.y);
            CellRange rr;
            if (in_row.n == 0 || !f.range(in_row.bounds(), rr)) continue;
            for (uint32_t z = std::max(rr.lo[2], r.lo[2]); z <= std::min(rr.hi[2], r.hi[2]); ++z)
                out.push_back(f.index(x, y, z));
        }
    }
}

/// Appends to `out` the linear indices of the cells of `f` that primitive `id` overlaps.
template <PrimitiveSet P>
void cells_of(const P& prims, uint32_t id, const GridFrame& f, GridAssign mode, std::vector<uint32_t>& out) {
    CellRange r;
    const Aabb b = prims.bounds(id);
    if (!f.range(b, r)) return;
    // One candidate cell that holds the whole primitive: nothing to clip.
    const Aabb wide = f.widened();
    const bool one_cell = r.single() && wide.contains(b.min) && wide.contains(b.max);
    constexpr bool can_clip = requires(uint32_t i, const Aabb& box) { prims.clip(i, box); };
    if constexpr (kHasTriangles<P>) {
        if (mode == GridAssign::Clip && !one_cell) {
            triangle_cells(prims.triangle(id), f, r, out);
            return;
        }
    }
    if (!can_clip || mode == GridAssign::Bounds || one_cell) {
        for (uint32_t z = r.lo[2]; z <= r.hi[2]; ++z)
            for (uint32_t y = r.lo[1]; y <= r.hi[1]; ++y)
                for (uint32_t x = r.lo[0]; x <= r.hi[0]; ++x) out.push_back(f.index(x, y, z));
        return;
    }
    for (uint32_t x = r.lo[0]; x <= r.hi[0]; ++x) {
        const Aabb slab = f.slab(0, x, wide);
        const Aabb in_slab = clipped_bounds(prims, id, slab);
        CellRange rs;
        if (in_slab.empty() || !f.range(in_slab, rs)) continue;
        for (uint32_t y = std::max(rs.lo[1], r.lo[1]); y <= std::min(rs.hi[1], r.hi[1]); ++y) {
            const Aabb in_row = clipped_bounds(prims, id, f.slab(1, y, slab));
            CellRange rr;
            if (in_row.empty() || !f.range(in_row, rr)) continue;
            for (uint32_t z = std::max(rr.lo[2], r.lo[2]); z <= std::min(rr.hi[2], r.hi[2]); ++z)
                out.push_back(f.index(x, y, z));
        }
    }
}

}  // namespace grid_detail

/// Appends the cell lists of frame `f` to `out`: one start offset per cell (in index order; the
/// caller adds the final sentinel) and, per cell, the entries of `ids` whose primitive overlaps it,
/// in the order of `ids`. Throws Error when the references would pass kMaxGridReferences.
template <PrimitiveSet P>
void append_cell_lists(const P& prims, std::span<const uint32_t> ids, const GridFrame& f, GridAssign mode,
                       CellLists& out, AssignScratch& s) {
    s.cells.clear();
    s.first.resize(ids.size() + 1);
    for (size_t k = 0; k < ids.size(); ++k) {
        s.first[k] = uint32_t(s.cells.size());
        grid_detail::cells_of(prims, ids[k], f, mode, s.cells);
        if (out.refs.size() + s.cells.size() > kMaxGridReferences)
            throw Error("grid: more than " + std::to_string(kMaxGridReferences) +
                        " primitive references (2^28); use fewer cells (smaller lambda or res)");
    }
    s.first[ids.size()] = uint32_t(s.cells.size());

    const uint32_t cells = f.cells();
    s.cursor.assign(cells, 0);
    for (uint32_t c : s.cells) ++s.cursor[c];
    uint32_t pos = uint32_t(out.refs.size());
    for (uint32_t c = 0; c < cells; ++c) {
        out.start.push_back(pos);
        const uint32_t n = s.cursor[c];
        s.cursor[c] = pos;
        pos += n;
    }
    out.refs.resize(pos);
    for (size_t k = 0; k < ids.size(); ++k)
        for (uint32_t i = s.first[k]; i < s.first[k + 1]; ++i) out.refs[s.cursor[s.cells[i]]++] = ids[k];
}

}  // namespace thicket
