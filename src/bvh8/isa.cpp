// ISA detection and selection for the bvh8 kernels. Compiled for the baseline: it only reads
// cpuid and returns pointers to the kernel tables each ISA's translation unit defines.
#include "thicket/bvh8/isa.h"

#include <cstdlib>

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

namespace {

bool cpu_has_avx2() {
    __builtin_cpu_init();
    // The AVX2 kernels are compiled with -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt (Haswell).
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
           __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("popcnt");
}

bool cpu_has_avx512() {
    return cpu_has_avx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
}

std::string list(const std::vector<Isa>& isas) {
    std::string out;
    for (Isa i : isas) out += (out.empty() ? "" : ", ") + std::string(isa_name(i));
    return out;
}

bool parse_level(const std::string& value, Isa& out) {
    for (Isa i : {Isa::Scalar, Isa::Sse, Isa::Avx2, Isa::Avx512})
        if (value == isa_name(i)) {
            out = i;
            return true;
        }
    return false;
}

}  // namespace

const char* isa_name(Isa isa) {
    switch (isa) {
    case Isa::Scalar: return "scalar";
    case Isa::Sse: return "sse";
    case Isa::Avx2: return "avx2";
    case Isa::Avx512: return "avx512";
    }
    return "?";
}

std::vector<Isa> cpu_isas() {
    std::vector<Isa> out{Isa::Scalar, Isa::Sse};
    if (cpu_has_avx2()) out.push_back(Isa::Avx2);
    if (cpu_has_avx512()) out.push_back(Isa::Avx512);
    return out;
}

Isa cpu_best_isa() { return cpu_isas().back(); }

Isa resolve_isa(const std::string& value) {
    const Isa best = cpu_best_isa();
    if (value == "auto") {
        const char* env = std::getenv("THICKET_ISA");
        if (!env || !*env) return best;
        Isa cap;
        if (!parse_level(env, cap))
            throw Error(std::string("THICKET_ISA=") + env + " is not a level; use scalar, sse, avx2 or avx512");
        if (cap > best)
            throw Error(std::string("THICKET_ISA=") + env + " asks for a level this CPU does not run; it has " +
                        list(cpu_isas()));
        return cap;
    }
    Isa isa;
    if (!parse_level(value, isa))
        throw Error("bvh8: isa=" + value + " is not a level; use auto, scalar, sse, avx2 or avx512");
    if (isa > best)
        throw Error("bvh8: isa=" + value + " is not supported by this CPU; it has " + list(cpu_isas()));
    return isa;
}

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
