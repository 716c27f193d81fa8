#pragma once
/// Run-time choice of the bvh8 traversal kernels: scalar reference, SSE2 (the x86-64 baseline),
/// AVX2+FMA, AVX-512VL, picked once by cpuid. The spec key `isa=` and the environment variable
/// THICKET_ISA select among them (docs/bvh8.md).
#include <string>
#include <vector>

#include "thicket/accel/choice.h"
#include "thicket/bvh8/node.h"

namespace thicket::bvh8 {

enum class Isa { Scalar = 0, Sse = 1, Avx2 = 2, Avx512 = 3 };

/// Every level by name, lowest first: the one table isa_name() and resolve_isa() (the spec's
/// `isa=` and THICKET_ISA) read, and bvh8's `isa` option lists after kAutoIsa.
inline constexpr Choice<Isa> kIsaLevels[] = {
    {"scalar", Isa::Scalar},
    {"sse", Isa::Sse},
    {"avx2", Isa::Avx2},
    {"avx512", Isa::Avx512},
};
/// The `isa` value that asks for the CPU's best level (capped by THICKET_ISA).
inline constexpr const char* kAutoIsa = "auto";

/// The level's name in kIsaLevels: "scalar", "sse", "avx2" or "avx512".
const char* isa_name(Isa isa);
/// Every level this CPU runs, lowest first (scalar and sse always).
std::vector<Isa> cpu_isas();
/// The highest level this CPU runs.
Isa cpu_best_isa();
/// The level a spec's `isa` value means: kAutoIsa is the CPU's best, capped by THICKET_ISA when
/// set; an explicit level must be one the CPU runs. Throws Error naming the value and the
/// allowed values (a value that is not a level) or the levels the CPU has (a level it lacks),
/// and likewise for THICKET_ISA.
Isa resolve_isa(const std::string& value);
/// The kernels of one level (which the CPU must run).
const KernelTable& kernels_for(Isa isa);

}  // namespace thicket::bvh8
