// The bvh8 kernels' choice judged by oracles that do not ask the code under test: the CPU flags
// that Linux reports (/proc/cpuinfo), and THICKET_EXPECT_ISA, the level a run demands (set by
// scripts/ctest-checked from scripts/expected-isa, which reads the same flags in the shell, or by
// hand to demand a level of a CI machine). A broken detection, or a machine that silently lacks
// AVX-512, then fails here instead of shrinking every per-ISA loop without a word.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/core/isa.h"
#include "thicket/render/camera.h"
#include "thicket/scene/scene.h"

namespace isa_oracle_test {

using namespace thicket;

namespace {

/// The first "flags" line of /proc/cpuinfo as a set; empty when there is none.
std::set<std::string> linux_cpu_flags() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("flags", 0) == 0) {
            std::istringstream words(line.substr(line.find(':') + 1));
            std::set<std::string> flags;
            for (std::string w; words >> w;) flags.insert(w);
            return flags;
        }
    return {};
}

/// The levels those flags allow, lowest first, by what each level's kernels are compiled with
/// (cmake/bvh8_isa.cmake): written from the flags' names, not from isa.cpp's checks.
std::vector<std::string> levels_allowed(const std::set<std::string>& f) {
    auto has = [&](std::initializer_list<const char*> names) {
        for (const char* n : names)
            if (!f.count(n)) return false;
        return true;
    };
    std::vector<std::string> levels = {"scalar", "sse"};
    // LZCNT's name is "abm"; some virtual machines' kernels leave it out while CPUID has the bit
    // (an AMD EPYC VM listing avx512f and bmi2). No CPU has BMI2 without LZCNT, so bmi2 stands in.
    const bool lzcnt = has({"abm"}) || has({"lzcnt"}) || has({"bmi2"});
    if (lzcnt && has({"avx2", "fma", "bmi1", "bmi2", "popcnt"})) {
        levels.push_back("avx2");
        if (has({"avx512f", "avx512vl"})) levels.push_back("avx512");
    }
    return levels;
}

std::string value_of(const Accel& accel, const std::string& key) {
    for (const auto& [k, v] : accel.stats().extra)
        if (k == key) return v;
    return "(none)";
}

/// Sets THICKET_ISA to `value` (unset when empty) for its lifetime, then puts back what was there.
class IsaCap {
public:
    explicit IsaCap(const char* value) {
        if (const char* old = std::getenv("THICKET_ISA")) saved_ = old, had_ = true;
        if (*value)
            setenv("THICKET_ISA", value, 1);
        else
            unsetenv("THICKET_ISA");
    }
    ~IsaCap() {
        if (had_)
            setenv("THICKET_ISA", saved_.c_str(), 1);
        else
            unsetenv("THICKET_ISA");
    }

private:
    std::string saved_;
    bool had_ = false;
};

/// Coherent camera rays from inside the Cornell box towards a corner: every 4x4 tile shares one
/// direction octant, so a batch of them is all packets.
std::vector<Ray> corner_rays(const Scene& scene) {
    const Aabb b = scene.bounds();
    const Camera camera(b.center(), b.max, {0, 1, 0}, 50.0f);
    std::vector<Ray> rays;
    for (int by = 0; by < 32; by += 4)
        for (int bx = 0; bx < 32; bx += 4)
            for (int y = by; y < by + 4; ++y)
                for (int x = bx; x < bx + 4; ++x) rays.push_back(camera.generate(float(x) + 0.5f, float(y) + 0.5f, 32, 32));
    return rays;
}

/// A file of the source tree (THICKET_TEST_DATA is tests/data).
std::string source_file(const std::string& name) {
    std::ifstream in(std::string(THICKET_TEST_DATA) + "/../../" + name);
    EXPECT_TRUE(in.good()) << name;
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The -m flags of the COMPILE_OPTIONS that cmake/bvh8_isa.cmake gives `kernels_file`.
std::set<std::string> cmake_machine_flags(const std::string& cmake, const std::string& kernels_file) {
    const size_t at = cmake.find(kernels_file);
    EXPECT_NE(at, std::string::npos) << kernels_file;
    const size_t open = cmake.find("COMPILE_OPTIONS \"", at), close = cmake.find('"', open + 17);
    std::set<std::string> flags;
    std::istringstream options(cmake.substr(open + 17, close - open - 17));
    for (std::string o; std::getline(options, o, ';');)
        if (o.rfind("-m", 0) == 0) flags.insert(o.substr(2));
    return flags;
}

/// The features scripts/expected-isa demands for `level` (the `has ...` words of the line that
/// echoes it), in GCC's spelling: /proc/cpuinfo's bmi1 is GCC's bmi, and has_lzcnt is lzcnt.
std::set<std::string> script_features(const std::string& script, const std::string& level) {
    const size_t echo = script.find("then echo " + level + "\n");
    EXPECT_NE(echo, std::string::npos) << level;
    const size_t start = script.rfind('\n', echo) + 1;
    std::istringstream words(script.substr(start, echo - start));
    std::set<std::string> out;
    bool listing = false;
    for (std::string w; words >> w;) {
        if (w == "has") listing = true;
        else if (w == "&&" || w == "then") listing = false;
        else if (w == "has_lzcnt;" || w == "has_lzcnt") out.insert("lzcnt");
        else if (listing) out.insert(w == "bmi1" ? "bmi" : w);
    }
    return out;
}

}  // namespace

// core/isa.h's feature lists are the one statement of what each level needs: the kernels are
// compiled with exactly those -m flags, and the shell oracle demands exactly those features.
TEST(IsaFeatures, OneListForCompilerDetectionAndOracle) {
    const std::set<std::string> avx2(std::begin(kAvx2Features), std::end(kAvx2Features));
    std::set<std::string> avx512 = avx2;
    avx512.insert(std::begin(kAvx512Features), std::end(kAvx512Features));
    const std::string cmake = source_file("cmake/bvh8_isa.cmake");
    EXPECT_EQ(cmake_machine_flags(cmake, "kernels_avx2.cpp"), avx2);
    EXPECT_EQ(cmake_machine_flags(cmake, "kernels_avx512.cpp"), avx512);
    const std::string script = source_file("scripts/expected-isa");
    EXPECT_EQ(script_features(script, "avx2"), avx2);
    EXPECT_EQ(script_features(script, "avx512"), avx512);
    EXPECT_TRUE(isa_features(Isa::Sse).empty());
    EXPECT_EQ(isa_features(Isa::Avx512).size(), std::size(kAvx512Features));
}

TEST(IsaOracle, DetectionAgreesWithTheCpuFlagsLinuxReports) {
    const std::set<std::string> flags = linux_cpu_flags();
    if (flags.empty()) GTEST_SKIP() << "/proc/cpuinfo has no flags line here: no independent oracle";
    std::vector<std::string> detected;
    for (Isa isa : cpu_isas()) detected.push_back(isa_name(isa));
    EXPECT_EQ(detected, levels_allowed(flags));
}

TEST(IsaOracle, TheExpectedKernelsAreChosenAndRun) {
    const char* expected = std::getenv("THICKET_EXPECT_ISA");
    if (!expected || !*expected)
        GTEST_SKIP() << "THICKET_EXPECT_ISA is not set (scripts/ctest-checked sets it from scripts/expected-isa)";
    const IsaCap uncapped("");  // the CPU's own choice, whatever the caller's THICKET_ISA says
    EXPECT_STREQ(isa_name(cpu_best_isa()), expected);

    // The structure a user gets (isa=auto) holds the expected level's kernel table, and a coherent
    // batch went through that table's packet kernel where the level has one (SSE, AVX-512), ray by
    // ray where it has none (AVX2).
    const Scene scene = load_scene("cornell");
    const std::vector<Ray> rays = corner_rays(scene);
    const auto accel = build_accel("bvh8", scene);
    EXPECT_EQ(value_of(*accel, "isa"), expected);
    std::vector<Hit> hits(rays.size());
    BatchOptions coherent;
    coherent.coherent = true;
    accel->intersect(rays, hits, coherent);
    const bool packets = std::string(expected) == "sse" || std::string(expected) == "avx512";
    EXPECT_EQ(value_of(*accel, "packet rays"), packets ? std::to_string(rays.size()) : "0");
}

TEST(IsaOracle, ThicketIsaCapsTheChoiceAndNothingElse) {
    // THICKET_ISA=sse gives the SSE kernels to isa=auto, and an explicit level still gets its own.
    const Scene scene = load_scene("cornell");
    {
        const IsaCap cap("sse");
        EXPECT_EQ(value_of(*build_accel("bvh8", scene), "isa"), "sse");
        EXPECT_EQ(value_of(*build_accel("bvh8:isa=scalar", scene), "isa"), "scalar");
    }
    const IsaCap none("");
    EXPECT_EQ(value_of(*build_accel("bvh8", scene), "isa"), isa_name(cpu_best_isa()));
}

}  // namespace isa_oracle_test
