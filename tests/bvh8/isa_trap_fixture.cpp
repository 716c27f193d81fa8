// Deliberate instances of the dispatch trap, for bvh8.isa_confinement_detects_trap: this unit is
// compiled with -mavx2 -mfma, like src/bvh8/kernels_avx2.cpp, and
// - takes the address of the shared inline thicket::hit_within_bounds, which emits it out of line
//   here as a weak symbol holding AVX instructions, the copy the linker may keep for everyone;
// - instantiates std::sort, whose out-of-line helpers are std:: functions holding AVX code.
// The confinement check must flag both.
#include <algorithm>
#include <vector>

#include "thicket/core/ray_box.h"

namespace thicket::bvh8_avx2 {

bool (*trap_within_bounds)(const Ray&, float, const Aabb&) = &thicket::hit_within_bounds;

/// Sorts v (the point is the AVX-compiled std:: instantiation it leaves behind).
float sorted_median_trap(std::vector<float>& v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0f : v[v.size() / 2] * 1.5f;
}

}  // namespace thicket::bvh8_avx2
