#pragma once
/// The instruction-set levels of the library's SIMD kernels and their run-time choice: the scalar
/// reference, SSE2 (the x86-64 baseline), AVX2+FMA and AVX-512VL, detected once by cpuid in
/// src/core/isa.cpp, the one file that knows the CPU. bvh8's traversal kernels are compiled once per
/// level (bvh8/isa.h: kernels_for) and the Embree peer is started at the same level. A port to
/// another architecture adds its levels to kIsaLevels, their features to kIsaFeatures, its
/// detection beside cpuid's, and a kernel table per level.
#include <span>
#include <string>
#include <vector>

#include "thicket/core/choice.h"

namespace thicket {

enum class Isa { Scalar = 0, Sse = 1, Avx2 = 2, Avx512 = 3 };

/// Every level by name, lowest first: the one table isa_name() and resolve_isa() (a spec's
/// `isa=` and THICKET_ISA) read, and bvh8's `isa` option lists after kAutoIsa.
inline constexpr Choice<Isa> kIsaLevels[] = {
    {"scalar", Isa::Scalar},
    {"sse", Isa::Sse},
    {"avx2", Isa::Avx2},
    {"avx512", Isa::Avx512},
};
/// The `isa` value that asks for the CPU's best level (capped by THICKET_ISA).
inline constexpr const char* kAutoIsa = "auto";

/// The CPU features a level needs beyond the level below it, as GCC's -m flags name them: what its
/// kernels are compiled with (cmake/bvh8_isa.cmake) and what detection checks before choosing it
/// (scripts/expected-isa reads the same list from /proc/cpuinfo). The test
/// `IsaFeatures.OneListForCompilerDetectionAndOracle` holds the three to this one list.
inline constexpr const char* kAvx2Features[] = {"avx2", "fma", "bmi", "bmi2", "lzcnt", "popcnt"};
inline constexpr const char* kAvx512Features[] = {"avx512f", "avx512vl"};
/// The features `isa` adds to the level below it (none for scalar and sse: the baseline).
std::span<const char* const> isa_features(Isa isa);

/// The level's name in kIsaLevels: "scalar", "sse", "avx2" or "avx512".
const char* isa_name(Isa isa);
/// Every level this CPU runs, lowest first (scalar and sse always).
std::vector<Isa> cpu_isas();
/// The highest level this CPU runs.
Isa cpu_best_isa();
/// The level an `isa` value means for `who` (the structure whose option it is, e.g. "bvh8"):
/// kAutoIsa is the CPU's best, capped by THICKET_ISA when set; an explicit level must be one the
/// CPU runs. Throws Error naming `who`, the value and the allowed values (a value that is not a
/// level) or the levels the CPU has (a level it lacks), and likewise for THICKET_ISA.
Isa resolve_isa(const std::string& value, const std::string& who);

}  // namespace thicket
