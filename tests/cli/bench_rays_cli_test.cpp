// `thicket bench --rays/--any-rays`: a user's own rays measured like the standard sets, read
// through the library's rows path (query/ray_rows.h) as `thicket trace` and the module read them.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "support/cli_run.h"
#include "support/temp_dir.h"
#include "thicket/util/npy.h"

namespace bench_rays_cli_test {

using thicket::testing::run_thicket;
using thicket::testing::shell_quote;

namespace {

std::string read_text(const std::string& path) {
    std::ifstream in(path);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

size_t count_of(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

}  // namespace

TEST(BenchRays, OwnRaysAreMeasuredAndRowsWithoutARayLeftOut) {
    const thicket::testing::TempDir dir("bench_rays");
    // Inside the built-in Cornell box (x, z in [-1, 1], y in [0, 2], open towards +z): a ray to
    // the back wall and one to the ceiling hit; one out through the open front misses; a NaN
    // row is no ray.
    const float nan = std::nanf("");
    const std::vector<float> rows = {
        0, 1, 0.5f, 0, 0, -1, 0, INFINITY,   // back wall
        0, 1, 3, 0, 0, 1, 0, INFINITY,       // away from the box
        0.1f, 1, 0, 0, 1, 0, 0, INFINITY,    // ceiling
        nan, 1, 0, 0, 1, 0, 0, INFINITY,     // not a ray
    };
    const std::string rays = dir.dir() + "/mine.npy";
    thicket::write_npy_f32(rays, {4, 8}, rows);
    const std::string json = dir.dir() + "/b.json";
    const auto r = run_thicket("bench cornell --accel bvh --accel grid --no-embree --reps 1 -j 1 --rays " +
                               shell_quote(rays) + " --any-rays " + shell_quote(rays) + " --json " + shell_quote(json));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("1 of 4 rows are not rays"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("2 ray sets,"), std::string::npos) << "only the file's sets run: " << r.output;
    const std::string text = read_text(json);
    // Two structures x two sets, each of the 3 rays; the standard sets did not run.
    EXPECT_EQ(count_of(text, "\"set\": \"mine.npy\""), 2u) << text;
    EXPECT_EQ(count_of(text, "\"set\": \"mine.npy (any hit)\""), 2u) << text;
    EXPECT_EQ(count_of(text, "\"set_rays\": 3,"), 4u) << text;
    EXPECT_EQ(count_of(text, "\"set\": \"primary\""), 0u) << text;
    EXPECT_EQ(count_of(text, "\"any_hit\": true"), 2u) << text;
    // Two of the three rays hit, for the closest hit and for occlusion, under both structures.
    EXPECT_EQ(count_of(text, "\"hit_rate\": 0.6666"), 4u) << text;
}

TEST(BenchRays, StandardSetsRunBesideOwnRaysWhenAsked) {
    const thicket::testing::TempDir dir("bench_rays_sets");
    const std::string rays = dir.dir() + "/r.npy";
    thicket::write_npy_f32(rays, {1, 8}, std::vector<float>{0, 1, 0.5f, 0, 0, -1, 0, INFINITY});
    const auto r = run_thicket("bench cornell --accel bvh --no-embree --reps 1 -j 1 --size 8x8 --sets primary --rays " +
                               shell_quote(rays));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("primary 64, r.npy 1"), std::string::npos) << r.output;
}

TEST(BenchRays, RefusedBeforeAnyWork) {
    const thicket::testing::TempDir dir("bench_rays_refused");
    const std::string rays = dir.dir() + "/r.npy";
    thicket::write_npy_f32(rays, {1, 8}, std::vector<float>{0, 1, 0.5f, 0, 0, -1, 0, INFINITY});
    // Rays belong to one scene.
    auto two = run_thicket("bench cornell teapot-patches --no-embree --rays " + shell_quote(rays));
    EXPECT_EQ(two.code, 1) << two.output;
    EXPECT_NE(two.output.find("give one SCENE (got 2)"), std::string::npos) << two.output;
    // A missing file is named.
    auto missing = run_thicket("bench cornell --no-embree --rays " + shell_quote(dir.dir() + "/none.npy"));
    EXPECT_EQ(missing.code, 1) << missing.output;
    EXPECT_NE(missing.output.find("none.npy"), std::string::npos) << missing.output;
    // A file of rows that are all without meaning has nothing to measure.
    const std::string bad = dir.dir() + "/bad.npy";
    thicket::write_npy_f32(bad, {1, 8}, std::vector<float>{0, 0, 0, 0, 0, 0, 0, INFINITY});
    auto empty = run_thicket("bench cornell --no-embree --rays " + shell_quote(bad));
    EXPECT_EQ(empty.code, 1) << empty.output;
    EXPECT_NE(empty.output.find("no row of its 1 is a ray"), std::string::npos) << empty.output;
}

}  // namespace bench_rays_cli_test
