// The AVX2+FMA kernels (Haswell and later): one 256-bit vector per node plane. Compiled with -mavx2 -mfma (cmake/bvh8_isa.cmake), so nothing here may be shared inline code.
#include <cstdint>
#include <immintrin.h>

#include "thicket/bvh8/node.h"
#include "thicket/core/ray_box.h"

namespace thicket::bvh8_avx2 {
#include "lanes_avx2.h"
#include "kernel_body.inc"
}  // namespace thicket::bvh8_avx2
