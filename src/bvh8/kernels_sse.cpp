// The SSE2 kernels: the x86-64 baseline, so compiled without extra flags; two 4-wide halves per node.
#include <cstdint>
#include <emmintrin.h>

#include "thicket/bvh8/node.h"
#include "thicket/core/ray_box.h"

namespace thicket::bvh8_sse {
#include "lanes_sse.h"
#include "kernel_body.inc"
}  // namespace thicket::bvh8_sse
