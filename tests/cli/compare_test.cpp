// `thicket compare` end to end on the built-in Cornell box with tiny sizes: every structure asked
// for gets its row and columns, the charts are well-formed with one series per structure, the JSON
// parses, existing files are never overwritten without --force, and bad options fail at once.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "support/cli_dir_test.h"
#include "support/xml_check.h"
#include "thicket/accel/registry.h"

namespace compare_cli_test {

namespace fs = std::filesystem;
using thicket::test::attribute_of;
using thicket::test::attribute_values;
using thicket::test::start_tags;
using thicket::test::xml_wellformedness_error;

namespace {

using Result = thicket::testing::CliResult;
using thicket::testing::shell_quote;

std::string read_all(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The table row of `accel`: the line that starts with it and a space.
std::string table_row(const std::string& output, const std::string& accel) {
    for (size_t p = 0; p < output.size();) {
        const size_t end = std::min(output.find('\n', p), output.size());
        const std::string line = output.substr(p, end - p);
        if (line.starts_with(accel + " ")) return line;
        p = end + 1;
    }
    return "";
}

std::vector<std::string> words(const std::string& line) {
    std::istringstream in(line);
    return {std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
}

}  // namespace

// Outside the anonymous namespace: the TEST_F classes derive from it (-Wsubobject-linkage in unity builds).
class CompareCliTest : public thicket::testing::CliDirTest {};

namespace {

// Small enough for the default suite: 36 triangles, growth at 100..1600 (made by subdivision),
// 32x24 rays, one timed pass.
const std::string kQuick = "compare cornell --sizes 100,400,1600 --fit-min 100 --size 32x24 --reps 1 --threads 2";

}  // namespace

TEST_F(CompareCliTest, TableChartsAndJsonCoverEveryStructure) {
    const std::vector<std::string> accels{"bvh", "bvh:builder=midpoint", "brute"};
    const Result r = run(kQuick + " --accel bvh --accel bvh:builder=midpoint --accel brute --json c.json");
    ASSERT_EQ(r.code, 0) << r.output;
    for (const char* column : {"structure", "partitioning", "build ms", "growth k", "B/prim", "SAH cost",
                               "primary Mrays/s 1t/2t", "primary nodes/prims", "diffuse Mrays/s 1t/2t",
                               "diffuse nodes/prims", "N=100", "N=400", "N=1.6k", "fit over"})
        EXPECT_NE(r.output.find(column), std::string::npos) << column << "\n" << r.output;
    for (const std::string& a : accels) {
        const std::string row = table_row(r.output, a);
        ASSERT_FALSE(row.empty()) << a << "\n" << r.output;
        EXPECT_NE(row.find(a == "brute" ? " none " : " object "), std::string::npos) << row;
    }
    // The fitted exponent of the BVH's build is a number, not a dash: structure, partitioning,
    // build ms, growth k.
    const std::vector<std::string> bvh = words(table_row(r.output, "bvh"));
    ASSERT_GE(bvh.size(), 4u);
    EXPECT_EQ(bvh[1], "object");
    EXPECT_EQ(bvh[3].size(), 4u) << bvh[3];
    EXPECT_GT(std::atof(bvh[3].c_str()), 0.3) << bvh[3];
    EXPECT_NE(r.output.find("100\u20131.6k, 3 sizes"), std::string::npos) << "the fit range is stated";

    const std::string growth = read_all(dir_ / "compare-plots" / "cornell-growth.svg");
    const std::string speed = read_all(dir_ / "compare-plots" / "cornell-mrays.svg");
    ASSERT_FALSE(growth.empty()) << "the default plot directory is compare-plots";
    ASSERT_FALSE(speed.empty());
    EXPECT_EQ(xml_wellformedness_error(growth), "");
    EXPECT_EQ(xml_wellformedness_error(speed), "");
    EXPECT_EQ(attribute_values(growth, "polyline", "data-series"), accels) << "one line per structure";
    for (const std::string& line : start_tags(growth, "polyline")) {
        // Three sizes drawn: "x,y x,y x,y".
        const std::vector<std::string> points = words(attribute_of(line, "points").value_or(""));
        EXPECT_EQ(points.size(), 3u) << line;
        for (const std::string& p : points) EXPECT_NE(p.find(','), std::string::npos) << line;
    }
    std::vector<std::string> groups = attribute_values(speed, "rect", "data-group");
    std::vector<std::string> series = attribute_values(speed, "rect", "data-series");
    ASSERT_EQ(groups.size(), 4 * accels.size()) << "primary and diffuse on 1 and 2 threads per structure";
    for (size_t i = 0; i < groups.size(); ++i) EXPECT_EQ(groups[i], accels[i / 4]);
    EXPECT_EQ(std::vector<std::string>(series.begin(), series.begin() + 4),
              (std::vector<std::string>{"primary, 1 thread", "primary, 2 threads", "diffuse, 1 thread",
                                        "diffuse, 2 threads"}));

    const nlohmann::json j = nlohmann::json::parse(read_all(dir_ / "c.json"));
    ASSERT_EQ(j["rows"].size(), accels.size());
    for (size_t i = 0; i < accels.size(); ++i) {
        const auto& row = j["rows"][i];
        EXPECT_EQ(row["accel"], accels[i]);
        EXPECT_EQ(row["primitives"], 36);
        EXPECT_EQ(row["growth"]["points"].size(), 3u);
        EXPECT_TRUE(row["growth"]["exponent"].is_number());
        EXPECT_EQ(row["speed"].size(), 4u);
        EXPECT_GT(row["speed"][0]["nodes_per_ray"].get<double>() + row["speed"][0]["prims_per_ray"].get<double>(), 0);
    }
    EXPECT_EQ(j["rows"][0]["partitioning"], "object");
    EXPECT_EQ(j["rows"][2]["partitioning"], "none");
}

TEST_F(CompareCliTest, NeverOverwritesWithoutForce) {
    Result r = run(kQuick + " --no-growth --json c.json");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "compare-plots" / "cornell-growth.svg")) << "no growth chart without a sweep";
    const fs::path chart = dir_ / "compare-plots" / "cornell-mrays.svg";
    ASSERT_TRUE(fs::exists(chart));
    std::ofstream(chart) << "mine";
    std::ofstream(dir_ / "other.json") << "mine too";

    r = run(kQuick + " --no-growth");
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("compare-plots/cornell-mrays.svg already exists"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("scene "), std::string::npos) << "refused before loading anything";
    EXPECT_EQ(read_all(chart), "mine");

    r = run(kQuick + " --no-growth --no-plots --json other.json");
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("other.json already exists"), std::string::npos) << r.output;
    EXPECT_EQ(read_all(dir_ / "other.json"), "mine too");

    r = run(kQuick + " --no-growth --force --json other.json");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(xml_wellformedness_error(read_all(chart)), "");
    EXPECT_TRUE(nlohmann::json::accept(read_all(dir_ / "other.json"))) << "other.json is not JSON";

    // A plot directory elsewhere; --no-plots writes none.
    r = run(kQuick + " --no-growth --plot-dir sub/plots");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir_ / "sub" / "plots" / "cornell-mrays.svg"));
}

TEST_F(CompareCliTest, DefaultStructuresAreEveryRegisteredOneButBruteForce) {
    const Result r = run("compare cornell --no-growth --no-plots --size 16x12 --reps 1 --markdown");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("| structure | partitioning |"), std::string::npos) << r.output;
    for (const thicket::AccelInfo& info : thicket::accel_registry()) {
        const bool listed = r.output.find("| " + info.name + " | ") != std::string::npos;
        EXPECT_EQ(listed, info.partitioning != thicket::Partitioning::None) << info.name << "\n" << r.output;
    }
    EXPECT_FALSE(fs::exists(dir_ / "compare-plots"));
}

TEST_F(CompareCliTest, BadOptionsFailBeforeAnyWork) {
    struct Case {
        std::string args, needle;
        int code;
    };
    const std::vector<Case> cases = {
        {"compare cornell --sizes 100,abc", "abc", 1},
        {"compare cornell --sizes 0", "'0'", 1},
        {"compare cornell --sizes 5000 --max-size 1000", "--max-size", 1},
        {"compare cornell --max-size 0", "--max-size", 1},
        {"compare cornell --accel nosuchaccel", "nosuchaccel", 1},
        {"compare cornell --size 10", "10", 1},
        {"compare cornell --reps 0", "--reps", 1},
        {"compare cornell --build-reps 0", "--build-reps", 1},
        {"compare no_such_scene.ply", "no_such_scene.ply", 1},
        {"compare cornell --plot-dir c.json/plots", "not a directory", 1},
        {"compare", "SCENE", 2},
    };
    std::ofstream(dir_ / "c.json") << "a file";
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const Result r = run(c.args);
        EXPECT_EQ(r.code, c.code) << r.output;
        EXPECT_NE(r.output.find(c.needle), std::string::npos) << r.output;
    }
    EXPECT_FALSE(fs::exists(dir_ / "compare-plots")) << "no directory made by a run that failed";
}

}  // namespace compare_cli_test
