// The scalar reference kernels: the same traversal with plain float code, lane by lane; what every SIMD kernel is checked against and the fallback of last resort.
#include <cstdint>

#include "thicket/bvh8/node.h"
#include "thicket/core/ray_box.h"

namespace thicket::bvh8_scalar {
#include "lanes_scalar.h"
#include "kernel_body.inc"
}  // namespace thicket::bvh8_scalar
