// The AVX-512VL kernels: 256-bit vectors with mask-register compares, as Embree runs them. Compiled with -mavx512f -mavx512vl (cmake/bvh8_isa.cmake), so nothing here may be shared inline code.
#include <cstdint>
#include <immintrin.h>

#include "thicket/bvh8/node.h"
#include "thicket/core/ray_box.h"

namespace thicket::bvh8_avx512 {
#include "lanes_avx512.h"
#include "kernel_body.inc"
}  // namespace thicket::bvh8_avx512
