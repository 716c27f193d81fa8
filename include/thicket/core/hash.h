#pragma once
/// FNV-1a 64-bit: a stable fingerprint for scenes and saved files (not for security).
#include <cstddef>
#include <cstdint>

namespace thicket {

inline constexpr uint64_t kFnvOffset = 1469598103934665603ull;

inline uint64_t fnv1a(const void* data, size_t bytes, uint64_t h = kFnvOffset) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

}  // namespace thicket
