// The scalar reference kernels: the same traversal with plain float code, lane by lane; what every SIMD kernel is checked against and the fallback of last resort.
#include <cstdint>


#include "thicket/bvh8/node.h"
#include "thicket/core/ray_box.h"

#define THICKET_BVH8_LEVEL 0
#define THICKET_BVH8_NAME "scalar"

namespace thicket::bvh8_scalar {
#include "kernel_body.inc"
}  // namespace thicket::bvh8_scalar
