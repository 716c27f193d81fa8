// Issue 31's CLI classes end to end: counts that size an allocation are checked against memory
// (never std::bad_alloc), float overflow in cameras and exposure is named where it happens,
// options that do not apply are refused instead of ignored, numbers are read strictly, and an
// image's format follows its extension or is refused.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/cli_dir_test.h"
#include "thicket/util/npy.h"

namespace refusals_test {

namespace fs = std::filesystem;
using thicket::testing::CliResult;
using thicket::testing::run_thicket;
using thicket::testing::shell_quote;

namespace {

class Refusals : public thicket::testing::CliDirTest {
protected:
    /// run() under an address-space limit (1.5 GB unless given).
    CliResult limited(const std::string& args, long kib = 1500000) const { return run_limited(args, kib); }
};

#ifndef THICKET_SANITIZED  // ulimit -v: AddressSanitizer's shadow memory cannot run under it
TEST_F(Refusals, CountsThatSizeAllocationsAreCheckedAgainstMemory) {
    // The example: 2^32 - 1 spheres (plus the ground and lights) cannot have ids at all.
    expect_refused(limited("cost --spheres 4294967295 --pixels 16 -a brute"), {"4294967295 spheres", "2^32 - 1"});
    expect_refused(limited("render spheres --spheres 4294967295 --integrator path -s 8x8 -o " + q("s.png")),
                   {"2^32 - 1"});
    // 40 million spheres have ids but not the memory under this limit: refused before allocating.
    expect_refused(limited("cost --spheres 40000000 --pixels 16 -a brute"), {"40000000 spheres", "needs", "GiB"});
    expect_refused(limited("render spheres --spheres 40000000 --integrator path -s 8x8 -o " + q("s.png")),
                   {"40000000 spheres", "needs"});
    // The shadow rays of 10^8 pixels and 64 lights.
    expect_refused(limited("cost --pixels 100000000 --lights 64 --spheres 10 -a brute"),
                   {"--pixels 100000000 with --lights 64", "needs"});
    EXPECT_FALSE(fs::exists(path("s.png")));
}

// trace --all with 2.5e6 crossings (500 stacked triangles, 5,000 rays through all of them): the
// lists would take 162 MiB; counted first and refused under a 120 MB limit (the 2e8
// crossings failed the same way at a larger scale).
TEST_F(Refusals, TraceAllChecksItsListsAgainstMemory) {
    {
        std::ofstream obj(path("stack.obj"));
        for (int i = 0; i < 500; ++i) obj << "v -10 -10 " << i * 0.01 << "\nv 30 -10 " << i * 0.01 << "\nv -10 30 " << i * 0.01 << "\n";
        for (int i = 0; i < 500; ++i) obj << "f " << 3 * i + 1 << " " << 3 * i + 2 << " " << 3 * i + 3 << "\n";
    }
    std::vector<float> rays;
    for (int i = 0; i < 5000; ++i) {
        const float x = float(i % 100) * 0.005f, y = float(i / 100) * 0.005f;
        rays.insert(rays.end(), {x, y, -1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 1e30f});
    }
    thicket::write_npy_f32(path("rays.npy"), {5000, 8}, rays);
    const CliResult r =
        limited("trace " + q("stack.obj") + " --accel bvh --rays " + q("rays.npy") + " --all -o " + q("all.npy"), 120000);
    expect_refused(r, {"--all: 2500000 crossings of 5000 rays", "needs"});
    EXPECT_FALSE(fs::exists(path("all.npy")));
}
#endif

TEST_F(Refusals, FloatOverflowInExposureAndCameraIsNamed) {
    const std::string render = "render cornell --integrator path --spp 1 -s 8x8 -o " + q("e.png") + " ";
    expect_refused(run(render + "--exposure 1e39"), {"--exposure 1e+39", "beyond float's range"});
    expect_refused(run(render + "--exposure 1e-50"), {"--exposure 1e-50", "below float's smallest"});
    expect_refused(run(render + "--exposure 0"), {"--exposure 0", "must be > 0"});
    expect_refused(run(render + "--time 1e400"), {"--time is infinite"});
    expect_refused(run("render cornell --view heatmap --heat-max 1e400 -s 8x8 -o " + q("h.png")),
                   {"--heat-max inf is not a finite node count"});
    // A view direction that itself passes float's range.
    expect_refused(run("render cornell -s 8x8 --camera -3e38,0,0,3e38,0,0 -o " + q("c.png")),
                   {"view direction passes float's range"});
    // A target at 1e20 straight ahead is the same view as one at 1: the same image, not 0% hits.
    CliResult r = run("render cornell -s 24x16 --camera 0,1,3.5,0,1,-1e20 -o " + q("far.png"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("66.7% hit"), std::string::npos) << r.output;
    r = run("render cornell -s 24x16 --camera 0,1,3.5,0,1,0 -o " + q("near.png"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(read("far.png"), read("near.png"));
    // `thicket rays` toward 1e20: every direction finite and of unit length.
    r = run("rays cornell --set primary -s 8x6 --camera 0,1,3.5,1e20,1,0 -o " + q("r.npy"));
    ASSERT_EQ(r.code, 0) << r.output;
    const thicket::NpyFloatArray m = thicket::read_npy_matrix(path("r.npy"), 8);
    ASSERT_EQ(m.shape[0], 48u);
    for (size_t i = 0; i < 48; ++i) {
        const float* row = &m.values[8 * i];
        ASSERT_TRUE(std::isfinite(row[3]) && std::isfinite(row[4]) && std::isfinite(row[5])) << "ray " << i;
        EXPECT_NEAR(row[3] * row[3] + row[4] * row[4] + row[5] * row[5], 1.0f, 1e-5f) << "ray " << i;
    }
}

TEST_F(Refusals, OptionsThatDoNotApplyAreRefused) {
    const std::string out = " -s 8x8 -o " + q("o.png");
    struct Case {
        std::string args;
        std::vector<std::string> fragments;
    };
    const Case cases[] = {
        {"render cornell --spp 4" + out, {"--spp does not apply", "--integrator"}},
        {"render cornell --seed 3" + out, {"--seed does not apply"}},
        {"render cornell --max-depth 3" + out, {"--max-depth does not apply"}},
        {"render cornell --time 1" + out, {"--time does not apply"}},
        {"render cornell --exposure 2" + out, {"--exposure does not apply"}},
        {"render cornell --integrator ''" + out, {"--integrator '' is empty"}},
        {"render cornell --integrator path --view heatmap" + out, {"--view does not apply", "preview"}},
        {"render cornell --integrator path --heat-max 5" + out, {"--heat-max does not apply"}},
        {"render cornell --view depth --heat-max 5" + out, {"--heat-max does not apply", "heatmap"}},
        {"render cornell --integrator path --spheres 30" + out, {"--spheres does not apply", "cornell"}},
        {"render cornell --lights 2" + out, {"--lights does not apply"}},
        {"info spheres", {"spheres: the lecture's generated scene", "thicket render"}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        expect_refused(run(c.args), c.fragments);
    }
    EXPECT_FALSE(fs::exists(path("o.png")));
    // `spheres` is a scene of the preview views too.
    const CliResult r = run("render spheres --spheres 30 --lights 2 -s 32x24 -o " + q("sp.png"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("30 spheres"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(path("sp.png")));
}

// --coherent is closest-hit's packet path: refused where no packet path would take it, before any
// output is written; taken with a closest-hit trace.
TEST_F(Refusals, CoherentIsRefusedWhereNoPacketPathTakesIt) {
    const std::vector<float> rays = {0, 1, 3, 0, 0, -1, 0, 1e30f, 0.2f, 1, 3, 0, 0, -1, 0, 1e30f};
    thicket::write_npy_f32(path("rays.npy"), {2, 8}, rays);
    const std::string trace = "trace cornell --coherent --rays " + q("rays.npy") + " -o " + q("h.npy");
    for (const char* query : {"--any-hit", "--count", "--all"}) {
        SCOPED_TRACE(query);
        expect_refused(run(trace + " " + query), {"--coherent does not apply here", query});
    }
    EXPECT_FALSE(fs::exists(path("h.npy")));
    const CliResult r = run(trace);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(path("h.npy")));
}

TEST_F(Refusals, NumbersAreReadStrictly) {
    const std::string render = "render cornell --integrator path --spp 1 -s 8x8 -o " + q("n.png") + " ";
    expect_refused(run(render + "--seed -1"), {"--seed", "'-1' is negative"}, 2);
    expect_refused(run(render + "--seed 1e23"), {"--seed", "'1e23' is not a whole number"}, 2);
    expect_refused(run(render + "--seed 18446744073709551616"), {"--seed", "larger than 18446744073709551615"}, 2);
    expect_refused(run("cost -j 100000 --pixels 16"), {"--threads", "'100000' is larger than 1024"}, 2);
    expect_refused(run("cost --spheres 2.5 --pixels 16"), {"--spheres", "'2.5' is not a whole number"}, 2);
    EXPECT_FALSE(fs::exists(path("n.png")));
    // The largest seed is a seed like any other.
    const CliResult r = run(render + "--seed 18446744073709551615");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("seed 18446744073709551615"), std::string::npos) << r.output;
}

TEST_F(Refusals, ImageFormatFollowsTheExtension) {
    expect_refused(run("render cornell -s 8x8 -o " + q("x.jpg")), {"x.jpg", "'.jpg'", ".png", ".exr"});
    expect_refused(run("render cornell -s 8x8 --integrator path --spp 1 -o " + q("x.jpg")), {"'.jpg'"});
    expect_refused(run("render cornell -s 8x8 -o " + q("noext")), {"noext", "no extension"});
    expect_refused(run("render cornell -s 8x8 -o " + q("x.exr")), {"x.exr", "preview views", "--integrator"});
    EXPECT_FALSE(fs::exists(path("x.jpg")));
    EXPECT_FALSE(fs::exists(path("x.exr")));
    // Upper case is the same format; EXR starts with its magic number, PNG with its signature.
    CliResult r = run("render cornell -s 8x8 --integrator path --spp 1 -o " + q("X.EXR"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(read("X.EXR").substr(0, 4), std::string("\x76\x2f\x31\x01", 4));
    r = run("render cornell -s 8x8 -o " + q("X.PNG"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(read("X.PNG").substr(1, 3), "PNG");
    // Special files without an extension get PNG.
    EXPECT_EQ(run("render cornell -s 8x8 -o /dev/null").code, 0);
    run("render cornell -s 8x8 -o - | cat > " + q("stdout.png"));  // the exit code is cat's
    EXPECT_EQ(read("stdout.png").substr(1, 3), "PNG");
}

}  // namespace

}  // namespace refusals_test
