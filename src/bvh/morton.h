#pragma once
// Internal to the BVH builders: the Morton order that lbvh splits and ploc clusters along.
#include <cstdint>
#include <span>
#include <vector>

#include "thicket/core/vec3.h"

namespace thicket::bvh_build {

/// Bits of each coordinate in a code: three axes interleaved in 63 bits.
inline constexpr int kMortonBitsPerAxis = 21;

/// Sorts `indices` (0..n-1 on entry, n = centroids.size()) along the Morton curve of the
/// centroids quantized in their bounding box (NaN and out-of-range coordinates clamp to the
/// box), ties by primitive id, and returns the code at each sorted position. Codes are computed
/// on up to `threads` threads; the result never depends on them.
std::vector<uint64_t> morton_sort(std::span<const Vec3> centroids, unsigned threads, std::vector<uint32_t>& indices);

/// Axis whose coordinate bit sits at code bit `bit` (x on 3i+2, y on 3i+1, z on 3i).
inline int morton_axis_of_bit(int bit) { return 2 - bit % 3; }

}  // namespace thicket::bvh_build
