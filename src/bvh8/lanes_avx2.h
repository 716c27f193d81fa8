// The AVX2+FMA level's lane helpers (see lanes_common.h): a node plane's 8 lanes in one 256-bit
// vector, blocks in 128-bit ones, compare masks read by movemask.
#include "lanes_common.h"
#include "lanes_m128.h"
#include "lanes_m256.h"

namespace {

inline constexpr const char* kIsaName = "avx2";
/// Whether the packet kernel traces packets (false: each ray alone). Not on AVX2: its 16-ray
/// vectors take two of the 16 ymm registers each, the packet's origins, directions and inverses
/// alone eighteen, and the spills made packets slower than single rays on every shared scene
/// (BENCHMARKS.md, "bvh8 on incoherent rays", Packets on AVX2). A packet kernel of 8 rays would
/// fit; until then, rays one by one.
inline constexpr bool kPackets = false;

/// Bits (from bit 0) of the node lanes where a <= b; lanes outside `valid` may be cleared already.
__attribute__((always_inline)) inline uint32_t le_bits(__m256 a, __m256 b, uint32_t) {
    return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_LE_OQ)));
}
/// `mask` (all node lanes) restricted to `valid`, where le_bits has not done it.
__attribute__((always_inline)) inline uint32_t keep_valid(uint32_t mask, uint32_t valid) { return mask & valid; }

/// Bit k set where lane k of a 16-lane compare result is true: two 8-lane movemasks.
__attribute__((always_inline)) inline uint32_t mask16(const v16i& m) {
    __m256i lo, hi;
    __builtin_memcpy(&lo, &m, sizeof lo);
    __builtin_memcpy(&hi, reinterpret_cast<const char*>(&m) + sizeof lo, sizeof hi);
    return uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(lo))) |
           uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps(hi))) << 8;
}

}  // namespace
