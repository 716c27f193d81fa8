// The AVX-512VL level's lane helpers (see lanes_common.h): as AVX2's, but node compares run
// under the valid lanes' mask register, and 16-lane masks come from one 512-bit test.
#include "lanes_common.h"
#include "lanes_m128.h"
#include "lanes_m256.h"

namespace {

inline constexpr const char* kIsaName = "avx512";
/// Whether the packet kernel traces packets (false: each ray alone).
inline constexpr bool kPackets = true;

/// Bits (from bit 0) of the node lanes where a <= b, already restricted to `valid`: one compare
/// into a mask register under the valid lanes.
__attribute__((always_inline)) inline uint32_t le_bits(__m256 a, __m256 b, uint32_t valid) {
    return uint32_t(_mm256_mask_cmp_ps_mask(__mmask8(valid), a, b, _CMP_LE_OQ));
}
/// `mask` restricted to the valid lanes: le_bits has done it.
__attribute__((always_inline)) inline uint32_t keep_valid(uint32_t mask, uint32_t) { return mask; }

/// Bit k set where lane k of a 16-lane compare result is true (all ones).
__attribute__((always_inline)) inline uint32_t mask16(const v16i& m) {
    return uint32_t(_mm512_test_epi32_mask((__m512i)m, (__m512i)m));
}

}  // namespace
