// Issue 16 end to end: outputs never clobber what is not theirs to replace (special files,
// symlinks, inputs, existing files without --force), inputs that are not regular files or do not
// fit in memory are refused naming the file and the size, and sizes and counts that would run
// for hours are refused before any work.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/cli_dir_test.h"
#include "thicket/util/npy.h"

namespace output_safety_test {

namespace fs = std::filesystem;
using thicket::testing::CliResult;
using thicket::testing::run_thicket;
using thicket::testing::shell_quote;

namespace {

class OutputSafety : public thicket::testing::CliDirTest {
protected:
    /// An error of ours (exit 1, "thicket: error: ") with every fragment, never a bad_alloc.
    static void expect_error(const CliResult& r, const std::vector<std::string>& fragments) {
        expect_refused(r, fragments);
        EXPECT_NE(r.output.find("thicket: error: "), std::string::npos) << r.output;
    }
};

const char* const kRays = "rays cornell --set primary --size 8x6 ";

TEST_F(OutputSafety, ASymlinkIsFollowedAndKept) {
    // To /dev/null: written through, the link (and the device) stay as they are.
    fs::create_symlink("/dev/null", path("sink.png"));
    CliResult r = run("render cornell --size 16x12 -o " + q("sink.png"));
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::is_symlink(path("sink.png")));
    EXPECT_TRUE(fs::is_character_file("/dev/null"));
    // To a file that does not exist yet: it is created, the link kept.
    fs::create_symlink("target.npy", path("link.npy"));
    r = run(std::string(kRays) + "-o " + q("link.npy"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::is_symlink(path("link.npy")));
    EXPECT_EQ(thicket::read_npy_matrix(path("target.npy"), 8).shape[0], 48u);
    // Overwriting it through the link needs --force, like any existing file.
    expect_error(run(std::string(kRays) + "-o " + q("link.npy")), {"already exists", "--force"});
    EXPECT_EQ(run(std::string(kRays) + "--force -o " + q("link.npy")).code, 0);
    EXPECT_TRUE(fs::is_symlink(path("link.npy")));
}

TEST_F(OutputSafety, AFifoIsWrittenThroughNotReplaced) {
    ASSERT_EQ(::mkfifo(path("pipe").c_str(), 0600), 0);
    // The reader must be there before thicket opens the FIFO: both run under one shell.
    const std::string cmd = "cd " + shell_quote(dir_.string()) + " && (cat pipe > got.npy & " + shell_quote(THICKET_CLI) +
                            " " + kRays + "-o pipe >/dev/null 2>&1; s=$?; wait; exit $s)";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    struct stat st {};
    ASSERT_EQ(::stat(path("pipe").c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode)) << "the FIFO was replaced";
    EXPECT_EQ(thicket::read_npy_matrix(path("got.npy"), 8).shape[0], 48u);
}

TEST_F(OutputSafety, DashWritesTheDataToStdoutAndTheMessagesToStderr) {
    const std::string cmd = "cd " + shell_quote(dir_.string()) + " && " + shell_quote(THICKET_CLI) + " " + kRays +
                            "-o - 2>messages.txt > rays.npy";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << read("messages.txt");
    EXPECT_EQ(thicket::read_npy_matrix(path("rays.npy"), 8).shape[0], 48u);
    EXPECT_NE(read("messages.txt").find("rays    primary"), std::string::npos) << read("messages.txt");
}

TEST_F(OutputSafety, AnOutputThatIsAnInputIsRefusedEvenWithForce) {
    ASSERT_EQ(run(std::string(kRays) + "-o " + q("r.npy")).code, 0);
    const std::string before = read("r.npy");
    expect_error(run("trace cornell --rays " + q("r.npy") + " -o " + q("r.npy") + " --force"), {"is the input"});
    EXPECT_EQ(read("r.npy"), before);
    write("tri.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    const std::string ply = read("tri.ply");
    expect_error(run("render " + q("tri.ply") + " --size 8x8 --force -o " + q("tri.ply")), {"is the input"});
    fs::create_symlink("tri.ply", path("alias.png"));
    expect_error(run("render " + q("tri.ply") + " --size 8x8 --force -o " + q("alias.png")), {"is the input"});
    EXPECT_EQ(read("tri.ply"), ply);
    expect_error(run("build " + q("tri.ply") + " --accel bvh --force -o " + q("tri.ply")), {"is the input"});
    EXPECT_EQ(read("tri.ply"), ply);
}

TEST_F(OutputSafety, RenderTraceAndRaysRefuseAnExistingFileWithoutForce) {
    ASSERT_EQ(run(std::string(kRays) + "-o " + q("r.npy")).code, 0);
    write("out.png", "keep");
    write("hits.npy", "keep");
    write("rays.npy", "keep");
    expect_error(run("render cornell --size 8x8 -o " + q("out.png")), {"out.png already exists", "--force"});
    expect_error(run("trace cornell --rays " + q("r.npy") + " -o " + q("hits.npy")), {"already exists"});
    expect_error(run(std::string(kRays) + "-o " + q("rays.npy")), {"already exists"});
    EXPECT_EQ(read("out.png"), "keep");
    EXPECT_EQ(read("hits.npy"), "keep");
    EXPECT_EQ(read("rays.npy"), "keep");
    EXPECT_EQ(run("render cornell --size 8x8 --force -o " + q("out.png")).code, 0);
    EXPECT_EQ(run("trace cornell --rays " + q("r.npy") + " -f -o " + q("hits.npy")).code, 0);
    EXPECT_EQ(run(std::string(kRays) + "--force -o " + q("rays.npy")).code, 0);
    EXPECT_EQ(thicket::read_npy_hits(path("hits.npy")).size(), 48u);
}

TEST_F(OutputSafety, ClosestRefusesAnExistingFileWithoutForceAndNeverItsInput) {
    const std::vector<float> points = {0.1f, 0.2f, 0.3f, 0.5f, 0.5f, 0.5f};
    thicket::write_npy_f32(path("points.npy"), {2, 3}, points);
    write("closest.npy", "keep");
    expect_error(run("closest cornell --points " + q("points.npy") + " -o " + q("closest.npy")),
                 {"closest.npy already exists", "--force"});
    EXPECT_EQ(read("closest.npy"), "keep");
    const std::string before = read("points.npy");
    expect_error(run("closest cornell --points " + q("points.npy") + " --force -o " + q("points.npy")),
                 {"is the input"});
    EXPECT_EQ(read("points.npy"), before);
    EXPECT_EQ(run("closest cornell --points " + q("points.npy") + " --force -o " + q("closest.npy")).code, 0);
    EXPECT_NE(read("closest.npy"), "keep");
}

TEST_F(OutputSafety, ReadOnlyFilesDirectoriesAndProcFilesAreRefusedClearly) {
    write("ro.png", "keep");
    fs::permissions(path("ro.png"), fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    expect_error(run("render cornell --size 8x8 --force -o " + q("ro.png")), {"ro.png", "read-only"});
    EXPECT_EQ(read("ro.png"), "keep");
    fs::create_directory(path("d.png"));
    expect_error(run("render cornell --size 8x8 --force -o " + q("d.png")), {"d.png", "is a directory"});
    expect_error(run("render cornell --size 8x8 --force -o /proc/version"), {"/proc/version", "read-only"});
}

TEST_F(OutputSafety, InputsThatAreNotRegularFilesAreRefusedNamingThem) {
    expect_error(run("info /dev/zero"), {"/dev/zero", "character device"});
    fs::create_symlink("/dev/zero", path("zero.ply"));
    expect_error(run("info " + q("zero.ply")), {"zero.ply", "character device"});
    fs::create_symlink("/dev/urandom", path("noise.obj"));
    expect_error(run("info " + q("noise.obj")), {"noise.obj", "character device"});
    expect_error(run("trace cornell --rays /dev/urandom -o " + q("h.npy")), {"/dev/urandom", "character device"});
    write("zero.obj", "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_error(run("info " + q("zero.obj")), {"/dev/zero", "character device"});
    fs::create_symlink("/dev/zero", path("zero.bvh"));
    expect_error(run("info cornell --load " + q("zero.bvh")), {"zero.bvh", "character device"});
}

// Limits on memory are set with ulimit -v, which AddressSanitizer's shadow memory cannot run under.
#ifndef THICKET_SANITIZED
TEST_F(OutputSafety, SizesAreCheckedAgainstMemoryBeforeAllocating) {
    const std::string limit = "ulimit -v 3000000; ";  // 3 GB of address space
    auto limited = [&](const std::string& args) {
        const std::string cmd = "cd " + shell_quote(dir_.string()) + " && (" + limit + shell_quote(THICKET_CLI) + " " + args + ") 2>&1";
        CliResult r;
        FILE* p = popen(cmd.c_str(), "r");
        char buf[4096];
        size_t n;
        while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
        const int status = pclose(p);
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return r;
    };
    expect_error(limited("render cornell --size 32768x32768 -o " + q("big.png")), {"--size 32768x32768", "needs 11.0 GiB"});
    expect_error(limited("rays cornell --set primary --size 16384x16384 -o " + q("big.npy")), {"16384x16384", "needs", "GiB"});
    // A sparse .npy announcing 150,000,000 rays (4.8 GB) that it does not hold.
    {
        std::string header = "\x93NUMPY\x01";
        header += '\0';
        std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (150000000, 8), }";
        dict.append(117 - dict.size(), ' ');  // 10 + 118 bytes: the data starts at 128
        dict += '\n';
        header += char(dict.size() & 0xFF);
        header += char(dict.size() >> 8);
        write("sparse.npy", header + dict);
        fs::resize_file(path("sparse.npy"), 128 + uint64_t(150000000) * 32);
    }
    expect_error(limited("trace cornell --rays " + q("sparse.npy") + " -o " + q("h.npy")), {"sparse.npy", "needs 4.5 GiB"});
    EXPECT_FALSE(fs::exists(path("big.png")));
}
#endif

TEST_F(OutputSafety, CountsThatWouldRunForYearsAreRefused) {
    expect_error(run("bench cornell --accel bvh --no-embree --reps 2000000000"), {"--reps 2000000000", "1000"});
    expect_error(run("bench cornell --accel bvh --no-embree --rounds 1000000"), {"--rounds"});
    expect_error(run("compare cornell --accel bvh --reps 5000"), {"--reps 5000"});
}

TEST_F(OutputSafety, CameraAndGeometryBeyondFloatAreNamed) {
    expect_error(run("render cornell --size 8x8 --camera 1e39,0,0,0,0,0 -o " + q("c.png")),
                 {"component 1 ('1e39')", "outside the range of float"});
    write("huge.obj", "v 0 0 0\nv 1e40 0 0\nv 0 nan 0\nv 1e38 1e38 1\nf 1 2 3\nf 1 4 3\n");
    const CliResult info = run("info " + q("huge.obj") + " --no-accel");
    EXPECT_EQ(info.code, 0) << info.output;
    EXPECT_NE(info.output.find("non-finite vertices  2"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("vertices beyond 1e18 1"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("warning: 2 vertices are NaN or infinite"), std::string::npos) << info.output;
    // An automatic camera for bounds of 1e38 cannot be placed in float: said, not a blank image.
    write("far.obj", "v -1e38 -1e38 -1e38\nv 1e38 1e38 1e38\nv 0 1e38 0\nf 1 2 3\n");
    expect_error(run("render " + q("far.obj") + " --size 8x8 -o " + q("far.png")), {"too large to frame", "--camera"});
    write("big.obj", "v -1e20 -1e20 -1e20\nv 1e20 1e20 1e20\nv 0 1e20 0\nf 1 2 3\n");
    const CliResult big = run("render " + q("big.obj") + " --size 8x8 -o " + q("big.png"));
    EXPECT_EQ(big.code, 0) << big.output;
    EXPECT_NE(big.output.find("warning: the camera stands at"), std::string::npos) << big.output;
}

TEST_F(OutputSafety, CompareOfAShapesOnlySceneSaysWhyInsteadOfCrashing) {
    const CliResult r = run("compare teapot-patches --accel bvh --sizes 1000 --size 8x8 --reps 1 --no-plots");
    expect_error(r, {"teapot-patches", "no triangles", "--no-growth"});
}

}  // namespace

}  // namespace output_safety_test
