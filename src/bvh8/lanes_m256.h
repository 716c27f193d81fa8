// Part of the bvh8 kernels' lane helpers (lanes_<isa>.h), included inside an ISA namespace: the
// 256-bit operations of the AVX2 and AVX-512VL levels, where a node plane's 8 lanes are one vector.
namespace {

using NodeLanes = __m256;
/// Node planes are tested kNodeLanes lanes at a time.
inline constexpr int kNodeLanes = 8;

/// 8 floats of a node plane (32-byte aligned).
__attribute__((always_inline)) inline __m256 node_load(const float* p) { return _mm256_load_ps(p); }
/// 8 quantized planes (QNode::q, 8 bytes), each zero-extended and converted exactly to float.
__attribute__((always_inline)) inline __m256 node_load_u8(const uint8_t* p) {
    return _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
}
/// x in every lane.
__attribute__((always_inline)) inline __m256 node_splat(float x) { return _mm256_set1_ps(x); }
__attribute__((always_inline)) inline __m256 node_zero() { return _mm256_setzero_ps(); }
/// The lanes to p (unaligned).
__attribute__((always_inline)) inline void node_store(float* p, __m256 v) { _mm256_storeu_ps(p, v); }

__attribute__((always_inline)) inline __m256 vadd(__m256 a, __m256 b) { return _mm256_add_ps(a, b); }
__attribute__((always_inline)) inline __m256 vsub(__m256 a, __m256 b) { return _mm256_sub_ps(a, b); }
__attribute__((always_inline)) inline __m256 vmul(__m256 a, __m256 b) { return _mm256_mul_ps(a, b); }
/// a * b + c with one rounding (FMA): the FMA slab test, whose error bound covers one or two.
__attribute__((always_inline)) inline __m256 node_muladd(__m256 a, __m256 b, __m256 c) { return _mm256_fmadd_ps(a, b, c); }
/// Lane-wise a < b ? a : b and a > b ? a : b (the second operand for a NaN).
__attribute__((always_inline)) inline __m256 vmin(__m256 a, __m256 b) { return _mm256_min_ps(a, b); }
__attribute__((always_inline)) inline __m256 vmax(__m256 a, __m256 b) { return _mm256_max_ps(a, b); }

/// Bit k set where lane k of a compare result is true (all ones): one movemask.
__attribute__((always_inline)) inline uint32_t mask8(const v8i& m) {
    return uint32_t(_mm256_movemask_ps(_mm256_castsi256_ps((__m256i)m)));
}

}  // namespace
