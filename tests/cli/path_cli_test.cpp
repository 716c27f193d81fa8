// `thicket render --integrator` and `thicket cost` end to end: the written image, thread-count
// determinism through the executable, and errors that name the bad option.
#include <gtest/gtest.h>

#include <tinyexr.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_run.h"
#include "support/png_read.h"
#include "support/temp_dir.h"
#include "thicket/render/film.h"
#include "thicket/render/image.h"

namespace path_cli_test {

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

// -o x.exr writes the linear radiance the PNG is tone-mapped from: read back with tinyexr, every
// value is finite and non-negative, and sRGB-encoding it gives the PNG of the same seed.
TEST(PathCli, ExrHoldsTheLinearRadianceOfThePng) {
    const thicket::testing::TempDir dir("thicket_path_cli");
    const std::string png = dir.dir() + "/c.png", exr = dir.dir() + "/c.exr";
    const std::string common = "render cornell --integrator path --spp 2 --seed 5 --size 24x20 --exposure 1.5 -o ";
    auto r = run_thicket(common + shell_quote(png));
    ASSERT_EQ(r.code, 0) << r.output;
    r = run_thicket(common + shell_quote(exr));
    ASSERT_EQ(r.code, 0) << r.output;
    int w = 0, h = 0, ew = 0, eh = 0;
    const auto pixels = read_png(png, w, h);
    float* rgba = nullptr;
    const char* err = nullptr;
    ASSERT_EQ(LoadEXR(&rgba, &ew, &eh, exr.c_str(), &err), TINYEXR_SUCCESS) << (err ? err : "");
    ASSERT_EQ(ew, w);
    ASSERT_EQ(eh, h);
    size_t mismatched = 0, bright = 0;
    for (int i = 0; i < w * h; ++i) {
        for (int c = 0; c < 3; ++c) {
            const float v = rgba[4 * i + c];
            ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << "pixel " << i << " channel " << c << ": " << v;
            bright += v > 1.0f;
            const thicket::Rgb8 encoded = thicket::to_rgb8(
                {thicket::srgb_encode(v), thicket::srgb_encode(v), thicket::srgb_encode(v)});
            if (std::abs(int(encoded.r) - int(pixels[3 * i + c])) > 1) ++mismatched;
        }
        EXPECT_EQ(rgba[4 * i + 3], 1.0f);
    }
    std::free(rgba);
    EXPECT_EQ(mismatched, 0u) << "EXR values that do not encode to the PNG's";
    EXPECT_GT(bright, 0u) << "the light (radiance > 1) is clamped in the PNG, not in the EXR";
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

}  // namespace path_cli_test
