// The kernel table of each ISA level (core/isa.h chooses the level). Compiled for the baseline: it
// only returns pointers to the tables each level's translation unit defines.
#include "thicket/bvh8/isa.h"

#include "thicket/core/error.h"

namespace thicket::bvh8_scalar {
const thicket::bvh8::KernelTable& kernels();
}
namespace thicket::bvh8_sse {
const thicket::bvh8::KernelTable& kernels();
}
namespace thicket::bvh8_avx2 {
const thicket::bvh8::KernelTable& kernels();
}
namespace thicket::bvh8_avx512 {
const thicket::bvh8::KernelTable& kernels();
}

namespace thicket::bvh8 {

const KernelTable& kernels_for(Isa isa) {
    switch (isa) {
    case Isa::Scalar: return bvh8_scalar::kernels();
    case Isa::Sse: return bvh8_sse::kernels();
    case Isa::Avx2: return bvh8_avx2::kernels();
    case Isa::Avx512: return bvh8_avx512::kernels();
    }
    throw Error("bvh8: unknown ISA level");
}

}  // namespace thicket::bvh8
