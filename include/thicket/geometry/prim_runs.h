#pragma once
/// How primitive ids interleave a mesh's triangles and a list of shapes. Plain data below both
/// the primitive sets (which lay out their arrays by it) and the scene (which records it while
/// loading), so that neither has to know the other.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace thicket {

/// A maximal range of consecutive ids of one kind: ids [first, first + count) are triangles
/// (or shapes) [index, index + count).
struct PrimRun {
    uint32_t first = 0;
    uint32_t count = 0;
    bool shapes = false;
    uint32_t index = 0;
};

/// Where a primitive id points: triangle `index` of the mesh, or shape `index` of the shapes.
struct PrimRef {
    bool shape = false;
    uint32_t index = 0;
};

/// The triangle or shape behind id `prim` given ascending `runs`; an empty `runs` means the
/// `triangles` triangles' ids come first, then the shapes'.
inline PrimRef locate_prim(const std::vector<PrimRun>& runs, uint32_t triangles, uint32_t prim) {
    if (runs.empty()) return prim < triangles ? PrimRef{false, prim} : PrimRef{true, prim - triangles};
    auto it = std::upper_bound(runs.begin(), runs.end(), prim, [](uint32_t p, const PrimRun& r) { return p < r.first; });
    if (it != runs.begin()) --it;
    return {it->shapes, it->index + (prim - it->first)};
}

}  // namespace thicket
