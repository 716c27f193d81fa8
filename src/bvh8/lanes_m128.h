// Part of the bvh8 kernels' lane helpers (lanes_<isa>.h), included inside an ISA namespace: the
// 128-bit operations of every SIMD level (SSE2 intrinsics, VEX-encoded under -mavx2). A
// 4-triangle block is one 128-bit vector per row on every SIMD level; node planes are on SSE2.
namespace {

using BlockLanes = __m128;
using BlockMask = __m128;  ///< all ones in the lanes that hold
inline constexpr int kBlockLanes = 4;

/// 4 floats from p, 16-byte aligned as block rows (and node planes) are.
__attribute__((always_inline)) inline __m128 block_load(const float* p) { return _mm_load_ps(p); }
/// x in every lane.
__attribute__((always_inline)) inline __m128 block_splat(float x) { return _mm_set1_ps(x); }
__attribute__((always_inline)) inline __m128 block_zero() { return _mm_setzero_ps(); }
/// The lanes to p (unaligned).
__attribute__((always_inline)) inline void block_store(float* p, __m128 v) { _mm_storeu_ps(p, v); }

__attribute__((always_inline)) inline __m128 vadd(__m128 a, __m128 b) { return _mm_add_ps(a, b); }
__attribute__((always_inline)) inline __m128 vsub(__m128 a, __m128 b) { return _mm_sub_ps(a, b); }
__attribute__((always_inline)) inline __m128 vmul(__m128 a, __m128 b) { return _mm_mul_ps(a, b); }
__attribute__((always_inline)) inline __m128 vdiv(__m128 a, __m128 b) { return _mm_div_ps(a, b); }
/// minps / maxps: lane-wise a < b ? a : b and a > b ? a : b (the second operand for a NaN).
__attribute__((always_inline)) inline __m128 vmin(__m128 a, __m128 b) { return _mm_min_ps(a, b); }
__attribute__((always_inline)) inline __m128 vmax(__m128 a, __m128 b) { return _mm_max_ps(a, b); }
/// Bitwise and / xor (signs, and the conjunction of compare masks).
__attribute__((always_inline)) inline __m128 vand(__m128 a, __m128 b) { return _mm_and_ps(a, b); }
__attribute__((always_inline)) inline __m128 vxor(__m128 a, __m128 b) { return _mm_xor_ps(a, b); }

/// Lane compares of blocks: != (true for NaN), >=, <= (ordered).
__attribute__((always_inline)) inline __m128 vne(__m128 a, __m128 b) { return _mm_cmpneq_ps(a, b); }
__attribute__((always_inline)) inline __m128 vge(__m128 a, __m128 b) { return _mm_cmpge_ps(a, b); }
__attribute__((always_inline)) inline __m128 vle(__m128 a, __m128 b) { return _mm_cmple_ps(a, b); }
/// Bit k set where lane k of the mask holds.
__attribute__((always_inline)) inline uint32_t mask_bits(__m128 m) { return uint32_t(_mm_movemask_ps(m)); }

}  // namespace
