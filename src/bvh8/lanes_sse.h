// The SSE2 level's lane helpers (see lanes_common.h): 128-bit vectors, so a node's 8 lanes are
// tested in two halves of 4; the packet kernel's compare masks are read lane by lane.
#include "lanes_common.h"
#include "lanes_m128.h"

namespace {

inline constexpr const char* kIsaName = "sse";
/// Node planes are tested kNodeLanes lanes at a time.
inline constexpr int kNodeLanes = 4;
/// Whether the packet kernel traces packets (false: each ray alone).
inline constexpr bool kPackets = true;

using NodeLanes = __m128;

/// kNodeLanes floats of a node plane (16-byte aligned).
__attribute__((always_inline)) inline __m128 node_load(const float* p) { return _mm_load_ps(p); }
/// kNodeLanes quantized planes (QNode::q, 4 bytes), zero-extended and converted exactly to float:
/// SSE2 has no byte-to-dword extension, so two unpacks with zero.
__attribute__((always_inline)) inline __m128 node_load_u8(const uint8_t* p) {
    int bytes;
    __builtin_memcpy(&bytes, p, sizeof bytes);
    const __m128i zero = _mm_setzero_si128();
    const __m128i words = _mm_unpacklo_epi8(_mm_cvtsi32_si128(bytes), zero);
    return _mm_cvtepi32_ps(_mm_unpacklo_epi16(words, zero));
}
__attribute__((always_inline)) inline __m128 node_splat(float x) { return _mm_set1_ps(x); }
__attribute__((always_inline)) inline __m128 node_zero() { return _mm_setzero_ps(); }
__attribute__((always_inline)) inline void node_store(float* p, __m128 v) { _mm_storeu_ps(p, v); }
/// a * b + c, rounded twice (SSE2 has no FMA): the FMA slab test's error bound covers it.
__attribute__((always_inline)) inline __m128 node_muladd(__m128 a, __m128 b, __m128 c) {
    return _mm_add_ps(_mm_mul_ps(a, b), c);
}

/// Bits (from bit 0) of the node lanes where a <= b; lanes outside `valid` may be cleared already.
__attribute__((always_inline)) inline uint32_t le_bits(__m128 a, __m128 b, uint32_t) {
    return uint32_t(_mm_movemask_ps(_mm_cmple_ps(a, b)));
}
/// `mask` (all node lanes) restricted to `valid`, where le_bits has not done it.
__attribute__((always_inline)) inline uint32_t keep_valid(uint32_t mask, uint32_t valid) { return mask & valid; }

using lanewise::mask16;
using lanewise::mask8;

}  // namespace
