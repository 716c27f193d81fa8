// Morton codes of centroids and the stable radix sort along them (lbvh and ploc).
#include "morton.h"

#include <algorithm>
#include <array>

#include "splitter.h"

namespace thicket::bvh_build {

namespace {

/// The 21 low bits of v spread to every third bit (bit i to bit 3i).
uint64_t spread_bits(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

}  // namespace

std::vector<uint64_t> morton_sort(std::span<const Vec3> c, unsigned threads, std::vector<uint32_t>& idx) {
    const uint32_t n = uint32_t(c.size());
    Aabb box;
    for (uint32_t i = 0; i < n; ++i) box.grow(c[i]);
    Vec3 scale;
    for (int a = 0; a < 3; ++a) {
        const float extent = box.max[a] - box.min[a];
        scale[a] = extent > 0.0f ? float((1u << kMortonBitsPerAxis) - 1) / extent : 0.0f;
    }
    std::vector<uint64_t> codes(n);
    parallel_for(n, kMinChunk, threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            uint64_t code = 0;
            for (int a = 0; a < 3; ++a) {
                const float f = (c[i][a] - box.min[a]) * scale[a];
                // NaN and out-of-range coordinates clamp, never an invalid cast.
                const uint64_t q = f > 0.0f ? uint64_t(std::min(f, float((1u << kMortonBitsPerAxis) - 1))) : 0;
                code |= spread_bits(q) << (2 - a);
            }
            codes[i] = code;
        }
    });
    // An LSD radix sort, stable: ties keep the ascending ids they start in.
    std::vector<uint32_t> tmp(n);
    for (int shift = 0; shift < 3 * kMortonBitsPerAxis; shift += 8) {
        std::array<size_t, 257> offset{};
        for (uint32_t i : idx) ++offset[((codes[i] >> shift) & 255) + 1];
        if (*std::max_element(offset.begin(), offset.end()) == n) continue;  // one digit: nothing moves
        for (size_t d = 1; d < offset.size(); ++d) offset[d] += offset[d - 1];
        for (uint32_t i : idx) tmp[offset[(codes[i] >> shift) & 255]++] = i;
        idx.swap(tmp);
    }
    std::vector<uint64_t> sorted(n);
    for (size_t k = 0; k < n; ++k) sorted[k] = codes[idx[k]];
    return sorted;
}

}  // namespace thicket::bvh_build
