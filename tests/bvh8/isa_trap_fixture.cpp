// A deliberate instance of the dispatch trap, for bvh8.isa_confinement_detects_trap: this unit is
// compiled with -mavx2 and instantiates std::sort, whose out-of-line helpers are emitted as weak
// std:: functions holding AVX instructions. The confinement check must flag them.
#include <algorithm>
#include <vector>

namespace thicket::bvh8_avx2 {

/// Sorts v (the only point is the AVX-compiled std:: instantiation it leaves behind).
float sorted_median_trap(std::vector<float>& v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0f : v[v.size() / 2] * 1.5f;
}

}  // namespace thicket::bvh8_avx2
