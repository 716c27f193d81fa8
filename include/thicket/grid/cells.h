#pragma once
/// The compact cell layout (Lagae & Dutre 2008): one offset per cell plus one entry per
/// reference, no vector of vectors. Cell c holds refs[start[c] .. start[c+1]). An entry is a
/// primitive id, with kSingleCell set when that primitive is referenced by no other cell (then
/// no mailbox is needed for it: it cannot be met twice).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace thicket {

inline constexpr uint32_t kSingleCell = 0x80000000u;
inline constexpr uint32_t kPrimMask = 0x7FFFFFFFu;

struct CellLists {
    std::vector<uint32_t> start;  ///< cells + 1 offsets into refs
    std::vector<uint32_t> refs;

    size_t cells() const { return start.empty() ? 0 : start.size() - 1; }
    uint32_t count(size_t c) const { return start[c + 1] - start[c]; }
    size_t bytes() const { return (start.size() + refs.size()) * sizeof(uint32_t); }
};

/// Sets kSingleCell on every entry whose primitive appears exactly once in `refs` (ids < prims).
inline void mark_single_cell_references(std::vector<uint32_t>& refs, size_t prims) {
    std::vector<uint8_t> seen(prims, 0);
    for (uint32_t r : refs) {
        uint8_t& s = seen[r & kPrimMask];
        if (s < 2) ++s;
    }
    for (uint32_t& r : refs)
        if (seen[r & kPrimMask] == 1) r |= kSingleCell;
}

}  // namespace thicket
