// The scalar level's lane helpers (see lanes_common.h): every "vector" is one float, so the
// kernels' chunk loops run lane by lane, the reference every SIMD level is checked against. No
// packet kernel: a packet's rays are traced one by one.
#include "lanes_common.h"

namespace {

inline constexpr const char* kIsaName = "scalar";
/// Node planes are tested kNodeLanes lanes at a time, 4-triangle blocks kBlockLanes at a time.
inline constexpr int kNodeLanes = 1;
inline constexpr int kBlockLanes = 1;
/// Whether the packet kernel traces packets (false: each ray alone).
inline constexpr bool kPackets = false;

using NodeLanes = float;
using BlockLanes = float;
using BlockMask = bool;

/// kNodeLanes / kBlockLanes floats from p, aligned as node planes and block rows are.
__attribute__((always_inline)) inline float node_load(const float* p) { return *p; }
__attribute__((always_inline)) inline float block_load(const float* p) { return *p; }
/// One quantized plane (QNode::q) as float (exact).
__attribute__((always_inline)) inline float node_load_u8(const uint8_t* p) { return float(*p); }
/// x in every lane.
__attribute__((always_inline)) inline float node_splat(float x) { return x; }
__attribute__((always_inline)) inline float block_splat(float x) { return x; }
__attribute__((always_inline)) inline float node_zero() { return 0.0f; }
__attribute__((always_inline)) inline float block_zero() { return 0.0f; }
/// The lanes to p (unaligned).
__attribute__((always_inline)) inline void node_store(float* p, float v) { *p = v; }
__attribute__((always_inline)) inline void block_store(float* p, float v) { *p = v; }

__attribute__((always_inline)) inline float vadd(float a, float b) { return a + b; }
__attribute__((always_inline)) inline float vsub(float a, float b) { return a - b; }
__attribute__((always_inline)) inline float vmul(float a, float b) { return a * b; }
__attribute__((always_inline)) inline float vdiv(float a, float b) { return a / b; }
/// a * b + c, rounded twice (the file is compiled with -ffp-contract=off): the FMA slab test's
/// error bound covers it.
__attribute__((always_inline)) inline float node_muladd(float a, float b, float c) { return a * b + c; }
/// a < b ? a : b and a > b ? a : b: the second operand when either is NaN, as minps and maxps.
__attribute__((always_inline)) inline float vmin(float a, float b) { return a < b ? a : b; }
__attribute__((always_inline)) inline float vmax(float a, float b) { return a > b ? a : b; }
/// Bitwise and / xor of the floats' bits (signs: x & -0.0f, x ^ sign).
__attribute__((always_inline)) inline float vand(float a, float b) {
    return __builtin_bit_cast(float, __builtin_bit_cast(uint32_t, a) & __builtin_bit_cast(uint32_t, b));
}
__attribute__((always_inline)) inline float vxor(float a, float b) {
    return __builtin_bit_cast(float, __builtin_bit_cast(uint32_t, a) ^ __builtin_bit_cast(uint32_t, b));
}

/// Lane compares of blocks (ordered, but != is true for NaN, as cmpneqps), their conjunction and
/// the bits of the lanes that hold.
__attribute__((always_inline)) inline bool vne(float a, float b) { return a != b; }
__attribute__((always_inline)) inline bool vge(float a, float b) { return a >= b; }
__attribute__((always_inline)) inline bool vle(float a, float b) { return a <= b; }
__attribute__((always_inline)) inline bool vand(bool a, bool b) { return a & b; }
__attribute__((always_inline)) inline uint32_t mask_bits(bool m) { return uint32_t(m); }

/// Bits (from bit 0) of the node lanes where a <= b; lanes outside `valid` may be cleared already.
__attribute__((always_inline)) inline uint32_t le_bits(float a, float b, uint32_t) { return uint32_t(a <= b); }
/// `mask` (all node lanes) restricted to `valid`, where le_bits has not done it.
__attribute__((always_inline)) inline uint32_t keep_valid(uint32_t mask, uint32_t valid) { return mask & valid; }

using lanewise::mask16;
using lanewise::mask8;

}  // namespace
