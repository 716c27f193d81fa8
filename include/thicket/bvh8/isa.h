#pragma once
/// bvh8's traversal kernels per ISA level (the levels, their detection and choice: core/isa.h):
/// each src/bvh8/kernels_<isa>.cpp compiles the same kernel text for its level, and
/// kernels_for() hands out that level's table. The spec key `isa=` and THICKET_ISA select the
/// level (docs/bvh8.md).
#include "thicket/bvh8/node.h"
#include "thicket/core/isa.h"

namespace thicket::bvh8 {

/// The kernels of one level (which the CPU must run).
const KernelTable& kernels_for(Isa isa);

}  // namespace thicket::bvh8
