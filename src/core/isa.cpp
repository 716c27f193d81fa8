// ISA detection and choice: the one file that asks the CPU what it runs. Compiled for the baseline.
#include "thicket/core/isa.h"

#include <cpuid.h>

#include <cstdlib>
#include <string_view>

#include "thicket/core/error.h"

namespace thicket {

namespace {

/// LZCNT (ABM): CPUID 0x80000001, ECX bit 5, read directly: GCC 12's __builtin_cpu_supports
/// has no name for it and clang 14 refuses "lzcnt".
bool cpu_has_lzcnt() {
    unsigned a = 0, b = 0, c = 0, d = 0;
    return __get_cpuid(0x80000001u, &a, &b, &c, &d) && (c & (1u << 5)) != 0;
}

/// Whether the CPU has one feature of kAvx2Features / kAvx512Features (__builtin_cpu_supports takes
/// literals only, hence one line each). A feature not named here is taken as missing, so a level
/// whose list grows without its detection is never chosen (and the features test fails).
bool cpu_has(std::string_view f) {
    __builtin_cpu_init();
    if (f == "avx2") return __builtin_cpu_supports("avx2");
    if (f == "fma") return __builtin_cpu_supports("fma");
    if (f == "bmi") return __builtin_cpu_supports("bmi");
    if (f == "bmi2") return __builtin_cpu_supports("bmi2");
    if (f == "popcnt") return __builtin_cpu_supports("popcnt");
    if (f == "lzcnt") return cpu_has_lzcnt();
    if (f == "avx512f") return __builtin_cpu_supports("avx512f");
    if (f == "avx512vl") return __builtin_cpu_supports("avx512vl");
    return false;
}

/// Each feature a level adds is checked, so an odd virtual CPU without one of them gets the level
/// below, not SIGILL.
bool cpu_runs(Isa isa) {
    for (const char* f : isa_features(isa))
        if (!cpu_has(f)) return false;
    return true;
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

std::span<const char* const> isa_features(Isa isa) {
    switch (isa) {
    case Isa::Avx2: return kAvx2Features;
    case Isa::Avx512: return kAvx512Features;
    default: return {};
    }
}

const char* isa_name(Isa isa) {
    for (const Choice<Isa>& c : kIsaLevels)
        if (c.value == isa) return c.name;
    return "?";
}

std::vector<Isa> cpu_isas() {
    std::vector<Isa> out{Isa::Scalar, Isa::Sse};
    if (cpu_runs(Isa::Avx2)) {
        out.push_back(Isa::Avx2);
        if (cpu_runs(Isa::Avx512)) out.push_back(Isa::Avx512);
    }
    return out;
}

Isa cpu_best_isa() { return cpu_isas().back(); }

Isa resolve_isa(const std::string& value, const std::string& who) {
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
        throw Error(who + ": isa=" + value + " is not allowed; choose one of " + level_names(kAutoIsa));
    if (level->value > best)
        throw Error(who + ": isa=" + value + " is not supported by this CPU; it has " + list(cpu_isas()));
    return level->value;
}

}  // namespace thicket
