// Part of the bvh8 kernels' lane helpers (lanes_<isa>.h), included inside an ISA namespace: the
// GCC generic vectors the packet kernel computes with (kernel_packet.inc), and the lane-by-lane
// forms of its compare masks for levels without a wider movemask. See kernel_body.inc for the
// rules every line here follows.
namespace {

typedef float v16f __attribute__((vector_size(64)));
typedef int v16i __attribute__((vector_size(64)));
typedef float v8f __attribute__((vector_size(32)));
typedef int v8i __attribute__((vector_size(32)));

namespace lanewise {

/// Bit k set where lane k of a compare result is true (all ones).
__attribute__((always_inline)) inline uint32_t mask16(const v16i& m) {
    uint32_t bits = 0;
    for (int k = 0; k < 16; ++k) bits |= uint32_t(m[k] != 0) << k;
    return bits;
}
/// The same for 8 lanes.
__attribute__((always_inline)) inline uint32_t mask8(const v8i& m) {
    uint32_t bits = 0;
    for (int k = 0; k < 8; ++k) bits |= uint32_t(m[k] != 0) << k;
    return bits;
}

}  // namespace lanewise

}  // namespace
