// THICKET_ISA through the tool: it caps the bvh8 kernels that `isa=auto` picks, what `info` and
// `bench` report is the level that runs, and a value that is not a level is refused by name.
#include <gtest/gtest.h>

#include <string>

#include "support/cli_run.h"
#include "thicket/bvh8/isa.h"

namespace isa_cli_test {

using thicket::testing::run_thicket;

namespace {

/// The value `thicket info` prints on its "isa" line, or "" without one.
std::string isa_line(const std::string& output) {
    const size_t at = output.find("\n  isa ");
    if (at == std::string::npos) return "";
    const size_t begin = output.find_first_not_of(' ', at + 7), end = output.find('\n', at + 1);
    return output.substr(begin, end - begin);
}

}  // namespace

TEST(IsaCli, ThicketIsaCapsWhatInfoAndBenchReport) {
    const auto best = run_thicket("info cornell --accel bvh8");
    ASSERT_EQ(best.code, 0) << best.output;
    EXPECT_EQ(isa_line(best.output), thicket::isa_name(thicket::cpu_best_isa())) << best.output;

    const auto sse = run_thicket("info cornell --accel bvh8", "", "THICKET_ISA=sse");
    ASSERT_EQ(sse.code, 0) << sse.output;
    EXPECT_EQ(isa_line(sse.output), "sse") << sse.output;

    const auto bench = run_thicket("bench cornell --accel bvh8 --no-embree --reps 1 -j 1 --sets primary --size 8x8", "",
                                   "THICKET_ISA=scalar");
    ASSERT_EQ(bench.code, 0) << bench.output;
    EXPECT_NE(bench.output.find("bvh8 runs the scalar kernels"), std::string::npos) << bench.output;
}

TEST(IsaCli, AValueThatIsNotALevelIsRefusedByName) {
    const auto r = run_thicket("info cornell --accel bvh8", "", "THICKET_ISA=avx9000");
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("THICKET_ISA=avx9000 is not a level"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("scalar, sse, avx2, avx512"), std::string::npos) << r.output;
}

}  // namespace isa_cli_test
