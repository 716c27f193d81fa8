// ISA detection and selection for the bvh8 kernels. Compiled for the baseline: it only reads
// cpuid and returns pointers to the kernel tables each ISA's translation unit defines.
#include "thicket/bvh8/isa.h"

#include <cpuid.h>

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

/// LZCNT (ABM): CPUID 0x80000001, ECX bit 5, read directly: GCC 12's __builtin_cpu_supports
/// has no name for it and clang 14 refuses "lzcnt".
bool cpu_has_lzcnt() {
    unsigned a = 0, b = 0, c = 0, d = 0;
    return __get_cpuid(0x80000001u, &a, &b, &c, &d) && (c & (1u << 5)) != 0;
}

bool cpu_has_avx2() {
    __builtin_cpu_init();
    // The AVX2 kernels are compiled with -mavx2 -mfma -mbmi -mbmi2 -mlzcnt -mpopcnt (Haswell): each
    // one is checked, so an odd virtual CPU without one of them gets the SSE kernels, not SIGILL.
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
           __builtin_cpu_supports("bmi2") && __builtin_cpu_supports("popcnt") && cpu_has_lzcnt();
}

bool cpu_has_avx512() {
    return cpu_has_avx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
}

std::string list(const std::vector<Isa>& isas) {
    std::string out;
    for (Isa i : isas) out += (out.empty() ? "" : ", ") + std::string(isa_name(i));
    return out;
}

/// Every name in kIsaLevels, comma-separated, after `first` when it is given.
std::string level_names(const char* first = nullptr) {
    std::string out = first ? first : "";
    for (const Choice<Isa>& c : kIsaLevels) out += (out.empty() ? "" : ", ") + std::string(c.name);
    return out;
}

const Choice<Isa>* find_level(const std::string& value) {
    for (const Choice<Isa>& c : kIsaLevels)
        if (value == c.name) return &c;
    return nullptr;
}

}  // namespace

const char* isa_name(Isa isa) {
    for (const Choice<Isa>& c : kIsaLevels)
        if (c.value == isa) return c.name;
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
    if (value == kAutoIsa) {
        const char* env = std::getenv("THICKET_ISA");
        if (!env || !*env) return best;
        const Choice<Isa>* cap = find_level(env);
        if (!cap)
            throw Error(std::string("THICKET_ISA=") + env + " is not a level; choose one of " + level_names());
        if (cap->value > best)
            throw Error(std::string("THICKET_ISA=") + env + " asks for a level this CPU does not run; it has " +
                        list(cpu_isas()));
        return cap->value;
    }
    const Choice<Isa>* level = find_level(value);
    if (!level)
        throw Error("bvh8: isa=" + value + " is not allowed; choose one of " + level_names(kAutoIsa));
    if (level->value > best)
        throw Error("bvh8: isa=" + value + " is not supported by this CPU; it has " + list(cpu_isas()));
    return level->value;
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
