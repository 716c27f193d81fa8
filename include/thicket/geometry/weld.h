#pragma once
/// Welding vertices by exact position: points compared bit for bit (so -0 and +0 are apart and a
/// NaN is only ever itself), as meshes exported face by face repeat a shared corner.
#include <array>
#include <cstdint>
#include <cstring>
#include <span>
#include <unordered_map>
#include <vector>

#include "thicket/core/vec3.h"

namespace thicket {

/// A point's three floats as bits: the key of an exact-position map.
using PointBits = std::array<uint32_t, 3>;

inline PointBits point_bits(const Vec3& p) {
    PointBits key;
    std::memcpy(key.data(), &p, sizeof key);
    return key;
}

/// Hashes three 32-bit words (a point's bits; tetra/build.cpp also a face's sorted vertex ids).
struct PointBitsHash {
    size_t operator()(const PointBits& k) const {
        return (size_t(k[0]) * 0x9E3779B97F4A7C15ull) ^ (size_t(k[1]) * 0xC2B2AE3D27D4EB4Full) ^
               (size_t(k[2]) + 0x165667B19E3779F9ull);
    }
};

/// For each of `positions`, the first index holding the same point bit for bit (its own index
/// when it is the first).
inline std::vector<uint32_t> weld_by_position(std::span<const Vec3> positions) {
    std::vector<uint32_t> welded(positions.size());
    std::unordered_map<PointBits, uint32_t, PointBitsHash> first;
    first.reserve(positions.size());
    for (uint32_t v = 0; v < positions.size(); ++v) welded[v] = first.try_emplace(point_bits(positions[v]), v).first->second;
    return welded;
}

}  // namespace thicket
