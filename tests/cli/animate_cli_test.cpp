// `thicket bench --animate`: the animated sequence prints a row per frame and structure (refit
// against rebuild) and a summary; what cannot refit, and options that belong to the standard
// bench, are refused naming them.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "support/cli_run.h"

namespace animate_cli_test {

using thicket::testing::run_thicket;

namespace {

size_t count_of(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST(BenchAnimate, PrintsEveryFrameOfEveryStructureAndASummary) {
    for (const std::string motion : {"bend", "explode"}) {
        const auto r = run_thicket("bench cornell --animate 3 --motion " + motion +
                                   " -a bvh8 -a bvh -a obb --reps 1 --size 16x12 -j 2 --sets primary,shadow");
        ASSERT_EQ(r.code, 0) << r.output;
        EXPECT_NE(r.output.find("3 frames, motion " + motion), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("refit ms"), std::string::npos) << r.output;
        for (const std::string spec : {"bvh8", "bvh", "obb"}) {
            EXPECT_EQ(count_of(r.output, "  " + spec + " "), 3u) << spec << ": one row per frame\n" << r.output;
            EXPECT_NE(r.output.find("summary " + spec + ": refit"), std::string::npos) << r.output;
        }
        // The refitted structures answer every ray as the rebuilt ones: each of their rows ends
        // with 100.00 in the agreement column. So does Embree's refit where this thicket has
        // Embree (an Embree that kept the rest pose would answer other rays).
        size_t rows = 0, embree_rows = 0;
        for (size_t at = 0, end; (end = r.output.find('\n', at)) != std::string::npos; at = end + 1) {
            const std::string line = r.output.substr(at, end - at);
            if (line.rfind("summary", 0) == 0) continue;
            const bool embree = line.find("  embree-refit ") != std::string::npos;
            if (line.find("  bvh") == std::string::npos && line.find("  obb ") == std::string::npos && !embree)
                continue;
            ++(embree ? embree_rows : rows);
            EXPECT_EQ(line.substr(line.size() - 7), " 100.00") << line;
        }
        EXPECT_EQ(rows, 9u) << r.output;
        EXPECT_TRUE(embree_rows == 0 || embree_rows == 3) << r.output;
        EXPECT_EQ(r.output.find("refused"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find("advice  rebuild"), std::string::npos) << r.output;
    }
}

TEST(BenchAnimate, RefusesWhatCannotRefitAndOptionsOfTheStandardBench) {
    auto r = run_thicket("bench cornell --animate 2 -a grid --no-embree --size 8x8");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("'grid"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("rebuild"), std::string::npos) << r.output;
    r = run_thicket("bench cornell --animate 2 --motion twist --no-embree");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("--motion 'twist'"), std::string::npos) << r.output;
    r = run_thicket("bench cornell --animate 2 --json out.json --no-embree");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("--json does not go with --animate"), std::string::npos) << r.output;
    r = run_thicket("bench cornell --animate 5000 --no-embree");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("between 1 and 1000"), std::string::npos) << r.output;
    r = run_thicket("bench cornell --motion explode --no-embree");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("--motion goes with --animate"), std::string::npos) << r.output;
    r = run_thicket("bench --help");
    EXPECT_NE(r.output.find("--animate"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--motion"), std::string::npos) << r.output;
}

}  // namespace animate_cli_test
