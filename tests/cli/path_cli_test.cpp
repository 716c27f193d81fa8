// `thicket render --integrator` and `thicket cost` end to end: the written image, thread-count
// determinism through the executable, and errors that name the bad option.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "support/cli_run.h"
#include "support/png_read.h"
#include "support/temp_dir.h"

namespace {

using thicket::testing::run_thicket;
using thicket::testing::shell_quote;

std::vector<unsigned char> read_png(const std::string& path, int& w, int& h) {
    std::string error;
    auto pixels = thicket::testing::read_png_rgb(path, w, h, error);
    EXPECT_FALSE(pixels.empty()) << path << ": " << error;
    return pixels;
}

TEST(PathCli, PathTracedCornellIsLitAndIndependentOfThreads) {
    const thicket::testing::TempDir dir("thicket_path_cli");
    const std::string a = dir.dir() + "/a.png", b = dir.dir() + "/b.png";
    auto r = run_thicket("render cornell --integrator path --spp 4 --seed 3 --size 48x40 --threads 1 -o " +
                         shell_quote(a));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("rays/s"), std::string::npos) << r.output;
    r = run_thicket("render cornell --integrator path --spp 4 --seed 3 --size 48x40 --threads 3 -o " + shell_quote(b));
    ASSERT_EQ(r.code, 0) << r.output;
    int w = 0, h = 0, w2 = 0, h2 = 0;
    const auto pa = read_png(a, w, h), pb = read_png(b, w2, h2);
    EXPECT_EQ(w, 48);
    EXPECT_EQ(h, 40);
    EXPECT_EQ(pa, pb) << "the same seed gives the same image on 1 and 3 threads";
    // The light is in view (top centre) and at least the walls are lit: not a black image.
    size_t lit = 0;
    for (unsigned char c : pa) lit += c > 20;
    EXPECT_GT(lit, pa.size() / 3);
}

TEST(PathCli, WhittedAndSpheresRender) {
    const thicket::testing::TempDir dir("thicket_path_cli");
    const std::string a = dir.dir() + "/w.png", b = dir.dir() + "/s.png";
    auto r = run_thicket("render cornell --integrator whitted --size 32x24 -o " + shell_quote(a));
    ASSERT_EQ(r.code, 0) << r.output;
    r = run_thicket("render spheres --spheres 50 --lights 2 --integrator path --spp 2 --size 32x24 -o " +
                    shell_quote(b));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("50 spheres"), std::string::npos) << r.output;
}

TEST(PathCli, BadOptionsAreNamed) {
    const thicket::testing::TempDir dir("thicket_path_cli");
    const std::string out = shell_quote(dir.dir() + "/x.png");
    struct Case {
        std::string args, needle;
    };
    const Case cases[] = {
        {"render cornell --integrator photon -o " + out, "photon"},
        {"render cornell --integrator path --spp 0 -o " + out, "--spp"},
        {"render cornell --integrator path --exposure -1 -o " + out, "--exposure"},
        {"render cornell --integrator path -o " + shell_quote(dir.dir() + "/x.exr"), "EXR"},
        {"render spheres --spheres 0 --integrator path -o " + out, "sphere count"},
        {"cost --pixels 0", "--pixels"},
        {"cost --accel nosuch --pixels 16", "nosuch"},
    };
    for (const Case& c : cases) {
        const auto r = run_thicket(c.args);
        EXPECT_EQ(r.code, 1) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << "\n" << r.output;
    }
}

TEST(PathCli, CostCountsFewerTestsWithAStructureThanBruteForce) {
    const auto r = run_thicket("cost --pixels 1024 --spheres 100 --lights 2 --accel brute --accel bvh");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("analytic brute force"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("brute"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("ns/test"), std::string::npos) << r.output;
    // The second column of the rows starting "brute" and "bvh": the counted tests.
    auto counted = [&](const std::string& name) {
        std::istringstream lines(r.output);
        std::string line;
        while (std::getline(lines, line))
            if (line.rfind(name, 0) == 0) {
                std::istringstream cells(line);
                std::string spec;
                double tests = -1;
                cells >> spec >> tests;
                return tests;
            }
        return -1.0;
    };
    const double brute = counted("brute"), bvh = counted("bvh");
    EXPECT_GT(brute, 0) << r.output;
    EXPECT_GT(bvh, 0) << r.output;
    EXPECT_LT(bvh * 3, brute) << r.output;
}

}  // namespace
