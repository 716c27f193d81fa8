// The `thicket` executable end to end: each test runs the built binary (THICKET_CLI) in a
// temporary directory and checks its files and exit codes against the library run in-process.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "support/cli_dir_test.h"
#include "support/probe.h"
#include "support/variant_cover.h"
#include "thicket/accel/registry.h"
#include "thicket/util/npy.h"

namespace cli_test {

namespace fs = std::filesystem;
using namespace thicket;

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

using RunResult = thicket::testing::CliResult;
using thicket::testing::run_thicket;
std::string quote(const std::string& s) { return thicket::testing::shell_quote(s); }
RunResult run_cli(const std::string& args) { return run_thicket(args); }

// The validity rule `thicket trace` documents: such rays are answered as misses.
bool valid_ray_row(const float* r) {
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(r[i])) return false;
    if (std::isnan(r[6]) || std::isnan(r[7]) || r[6] > r[7]) return false;
    return !(r[3] == 0 && r[4] == 0 && r[5] == 0);
}

Ray row_to_ray(const float* r) {
    Ray ray;
    ray.org = {r[0], r[1], r[2]};
    ray.dir = {r[3], r[4], r[5]};
    ray.tmin = r[6];
    ray.tmax = r[7];
    return ray;
}

// Answers of `accel` in the CLI's output conventions (t = +inf and prim = kNoPrim on a miss).
void expected_answers(const Accel& accel, const std::vector<float>& rows, std::vector<Hit>& hits,
                      std::vector<uint8_t>& occluded) {
    const size_t n = rows.size() / 8;
    hits.assign(n, Hit{});
    occluded.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
        const float* r = &rows[8 * i];
        if (!valid_ray_row(r)) continue;
        const Hit h = accel.intersect(row_to_ray(r));
        if (h.found()) hits[i] = h;
        occluded[i] = accel.occluded(row_to_ray(r)) ? 1 : 0;
    }
}

bool identical(const Hit& a, const Hit& b) {
    return a.prim == b.prim && (a.t == b.t || (std::isinf(a.t) && std::isinf(b.t))) && a.u == b.u && a.v == b.v;
}

// The suite's agreement rule (support/probe.h: a different primitive must really be hit at the
// reported t, u, v), with the CLI's convention that a miss has t = +inf.
bool agrees(const Hit& got, const Hit& want, const float* row, const thicket::testing::PrimitiveProbe& probe) {
    if (!got.found()) return !want.found() && std::isinf(got.t);
    return thicket::testing::same_closest_hit(got, want, row_to_ray(row), probe);
}

std::string describe(const std::vector<float>& rows, size_t i, const Hit& got, const Hit& want) {
    char buf[400];
    const float* r = &rows[8 * i];
    std::snprintf(buf, sizeof buf,
                  "ray %zu org (%.9g, %.9g, %.9g) dir (%.9g, %.9g, %.9g) t [%.9g, %.9g]: got prim %u t %.9g, "
                  "want prim %u t %.9g",
                  i, r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], got.prim, got.t, want.prim, want.t);
    return buf;
}

void push_ray(std::vector<float>& rows, Vec3 o, Vec3 d, float tmin = 0.0f, float tmax = kInfinity) {
    rows.insert(rows.end(), {o.x, o.y, o.z, d.x, d.y, d.z, tmin, tmax});
}

// Rays into the built-in Cornell box (open side toward +z): hits, misses, axis-parallel rays with
// signed zeros, clipped windows, an unnormalised direction, and invalid rows.
std::vector<float> cornell_rays() {
    std::vector<float> rows;
    const Vec3 eye{0.0f, 1.0f, 3.5f};
    // A fan through the opening and past its edges, aimed at a grid on the plane z = -1.
    for (int j = 0; j < 9; ++j)
        for (int i = 0; i < 9; ++i)
            push_ray(rows, eye, Vec3{-3.0f + 0.75f * float(i), -2.0f + 0.75f * float(j), -1.0f} - eye);
    push_ray(rows, eye, {0, 0, 1});                          // away from the box: miss
    push_ray(rows, {0.1f, 1.0f, 3.0f}, {0, 0, -1});          // axis-parallel
    push_ray(rows, {0.2f, 1.5f, 0.2f}, {-0.0f, -1, 0.0f});   // axis-parallel, signed zeros
    push_ray(rows, {-0.3f, 0.5f, 0.0f}, {1, 0, 0});          // axis-parallel toward the right wall
    push_ray(rows, eye, {0, -0.2f, -1}, 0.0f, 0.5f);         // window ends before the box: miss
    push_ray(rows, eye, {0, -0.2f, -1}, 3.0f, 100.0f);       // window starts inside the box
    push_ray(rows, eye, Vec3{0.1f, -0.3f, -1} * 3.0f);       // unnormalised direction
    push_ray(rows, eye, {0, 0, -1}, 2.0f, 1.0f);             // tmin > tmax: invalid
    push_ray(rows, eye, {kNaN, 0, -1});                      // NaN: invalid
    push_ray(rows, eye, {0, 0, 0});                          // zero direction: invalid
    push_ray(rows, {kInfinity, 1, 1}, {-1, 0, 0});           // infinite origin: invalid
    return rows;
}

size_t png_size(const std::string& path, int& width, int& height) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (bytes.size() < 24 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 || bytes.compare(12, 4, "IHDR") != 0)
        return 0;
    auto be32 = [&](size_t at) {
        return int((uint8_t(bytes[at]) << 24) | (uint8_t(bytes[at + 1]) << 16) | (uint8_t(bytes[at + 2]) << 8) |
                   uint8_t(bytes[at + 3]));
    };
    width = be32(16);
    height = be32(20);
    return bytes.size();
}

}  // namespace

// Outside the anonymous namespace: the TEST_F classes derive from it (-Wsubobject-linkage in unity builds).
class CliTest : public thicket::testing::CliDirTest {
protected:
    // Nothing but `expected` files in the directory (no outputs or temporaries of failed runs).
    void expect_only(std::vector<std::string> expected) const {
        std::vector<std::string> names;
        for (const auto& e : fs::recursive_directory_iterator(dir_)) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        std::sort(expected.begin(), expected.end());
        EXPECT_EQ(names, expected);
    }
};

namespace {

}  // namespace

TEST_F(CliTest, AccelsHelpAndVersion) {
    RunResult r = run_cli("accels");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("bvh"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("brute"), std::string::npos) << r.output;

    r = run_cli("--help");
    EXPECT_EQ(r.code, 0);
    for (const char* cmd : {"render", "trace", "info", "build", "accels"})
        EXPECT_NE(r.output.find(cmd), std::string::npos) << cmd;
    r = run_cli("trace --help");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.output.find("cornell"), std::string::npos) << "SCENE help names the built-in scenes";
    EXPECT_NE(r.output.find("--any-hit"), std::string::npos);
    r = run_cli("--version");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.output.find("thicket"), std::string::npos);

    r = run_cli("");
    EXPECT_EQ(r.code, 2) << "no subcommand is a usage error";
    r = run_cli("trace cornell");
    EXPECT_EQ(r.code, 2) << "missing --rays is a usage error";
    EXPECT_NE(r.output.find("--rays"), std::string::npos) << r.output;
}

TEST_F(CliTest, RenderWritesPngOfTheRequestedSize) {
    RunResult r = run_cli("render cornell --view normal --size 64x48 -o " + q("X.png"));
    ASSERT_EQ(r.code, 0) << r.output;
    int w = 0, h = 0;
    EXPECT_GT(png_size(path("X.png"), w, h), 0u);
    EXPECT_EQ(w, 64);
    EXPECT_EQ(h, 48);

    r = run_cli("render cornell --view heatmap --size 200x150 --threads 2 -o " + q("sub/dir/heat.png"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("nodes visited per ray"), std::string::npos) << r.output;
    EXPECT_GT(png_size(path("sub/dir/heat.png"), w, h), 0u) << "parent directories are created";
    EXPECT_EQ(w, 200);

    r = run_cli("render cornell --view depth --accel brute --size 32x32 --camera 0,1,3.5,0,1,0,50 -o " + q("d.png"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_GT(png_size(path("d.png"), w, h), 0u);
}

TEST_F(CliTest, TraceMatchesBruteForceInProcess) {
    const std::vector<float> rows = cornell_rays();
    write_npy_f32(path("rays.npy"), {rows.size() / 8, 8}, rows);
    const Scene scene = load_scene("cornell");
    std::vector<Hit> want;
    std::vector<uint8_t> want_occluded;
    expected_answers(*build_accel("brute", scene), rows, want, want_occluded);
    const thicket::testing::PrimitiveProbe probe(scene, "moller");
    size_t hits = 0;
    for (const Hit& h : want) hits += h.found();
    ASSERT_GT(hits, 20u) << "the ray set should hit the box often";
    ASSERT_LT(hits, want.size() - 20) << "and miss often";

    // --force below: each structure's run replaces the last one's outputs.
    for (const char* accel : {"brute", "bvh"}) {
        SCOPED_TRACE(accel);
        RunResult r = run_cli(std::string("trace cornell --accel ") + accel + " --rays " + q("rays.npy") + " --force -o " +
                              q("hits.npy"));
        ASSERT_EQ(r.code, 0) << r.output;
        EXPECT_NE(r.output.find("4 rays were invalid"), std::string::npos) << r.output;
        const std::vector<Hit> got = read_npy_hits(path("hits.npy"));
        ASSERT_EQ(got.size(), want.size());
        for (size_t i = 0; i < got.size(); ++i) {
            if (std::string(accel) == "brute")
                EXPECT_TRUE(identical(got[i], want[i])) << describe(rows, i, got[i], want[i]);
            else
                EXPECT_TRUE(agrees(got[i], want[i], &rows[8 * i], probe)) << describe(rows, i, got[i], want[i]);
        }

        r = run_cli(std::string("trace cornell --any-hit --threads 3 --accel ") + accel + " --rays " + q("rays.npy") +
                    " --force -o " + q("occluded.npy"));
        ASSERT_EQ(r.code, 0) << r.output;
        EXPECT_EQ(read_npy_u8(path("occluded.npy")), want_occluded);
    }
}

TEST_F(CliTest, BadInputsFailWithoutOutput) {
    const std::vector<float> rows = cornell_rays();
    write_npy_f32(path("rays.npy"), {rows.size() / 8, 8}, rows);
    write_npy_f32(path("rays7.npy"), {2, 7}, std::vector<float>(14, 1.0f));
    {
        std::ofstream bad(path("bad.npy"), std::ios::binary);
        bad << "\x93NUMPY\x01\x00\x10\x00{'descr': '<f4'";
    }
    struct Case {
        std::string args;
        std::string needle;  // what the message must name
        int code;
    };
    const std::string missing = path("no_such_scene.ply");
    const std::vector<Case> cases = {
        {"render " + quote(missing) + " -o " + q("out.png"), missing, 1},
        {"render cornell --accel nosuchaccel -o " + q("out.png"), "nosuchaccel", 1},
        {"render cornell --accel bvh:bins=zzz -o " + q("out.png"), "bins", 1},
        {"render cornell --view phong -o " + q("out.png"), "phong", 1},
        {"render cornell --size 64 -o " + q("out.png"), "--size", 1},
        {"render cornell --camera 1,2,3 -o " + q("out.png"), "--camera", 1},
        {"render cornell --accel bvh --load x.bvh -o " + q("out.png"), "--load", 2},
        {"trace cornell --rays " + q("bad.npy") + " -o " + q("out.npy"), path("bad.npy"), 1},
        {"trace cornell --rays " + q("rays7.npy") + " -o " + q("out.npy"), "(N, 8)", 1},
        {"trace cornell --rays " + q("missing.npy") + " -o " + q("out.npy"), path("missing.npy"), 1},
        {"trace " + quote(missing) + " --rays " + q("rays.npy") + " -o " + q("out.npy"), missing, 1},
        {"trace cornell --load " + q("missing.bvh") + " --rays " + q("rays.npy") + " -o " + q("out.npy"),
         path("missing.bvh"), 1},
        {"trace cornell --rays " + q("rays.npy") + " -o " + q("no/such/dir/out.npy"), "no/such/dir/out.npy", 1},
        {"build cornell -o " + q("out.bvh"), "--accel", 2},
        {"info " + quote(missing), missing, 1},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const RunResult r = run_cli(c.args);
        EXPECT_EQ(r.code, c.code) << r.output;
        EXPECT_NE(r.output.find(c.needle), std::string::npos) << r.output;
        if (c.code == 1) {
            EXPECT_NE(r.output.find("thicket: error: "), std::string::npos) << r.output;
        }
    }
    expect_only({"rays.npy", "rays7.npy", "bad.npy"});
}

TEST_F(CliTest, BuildThenTraceLoadedStructure) {
    const std::vector<float> rows = cornell_rays();
    write_npy_f32(path("rays.npy"), {rows.size() / 8, 8}, rows);
    const std::string spec = "bvh:builder=sweep-sah,max-leaf=2";
    RunResult r = run_cli("build cornell --accel " + spec + " -o " + q("s.bvh"));
    ASSERT_EQ(r.code, 0) << r.output;
    ASSERT_TRUE(fs::exists(path("s.bvh")));

    r = run_cli("trace cornell --load " + q("s.bvh") + " --rays " + q("rays.npy") + " -o " + q("hits.npy"));
    ASSERT_EQ(r.code, 0) << r.output;
    std::vector<Hit> want;
    std::vector<uint8_t> want_occluded;
    expected_answers(*build_accel(spec, load_scene("cornell")), rows, want, want_occluded);
    const std::vector<Hit> got = read_npy_hits(path("hits.npy"));
    ASSERT_EQ(got.size(), want.size());
    for (size_t i = 0; i < got.size(); ++i) EXPECT_TRUE(identical(got[i], want[i])) << describe(rows, i, got[i], want[i]);
    r = run_cli("trace cornell --any-hit --load " + q("s.bvh") + " --rays " + q("rays.npy") + " -o " + q("occ.npy"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(read_npy_u8(path("occ.npy")), want_occluded);
    r = run_cli("render cornell --load " + q("s.bvh") + " --size 40x30 -o " + q("r.png"));
    EXPECT_EQ(r.code, 0) << r.output;
    r = run_cli("info cornell --load " + q("s.bvh"));
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("SAH cost"), std::string::npos) << r.output;

    // No silent overwrite; --force replaces the file.
    const auto size_before = fs::file_size(path("s.bvh"));
    r = run_cli("build cornell --accel bvh:builder=midpoint -o " + q("s.bvh"));
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("already exists"), std::string::npos) << r.output;
    EXPECT_EQ(fs::file_size(path("s.bvh")), size_before);
    r = run_cli("build cornell --accel bvh:builder=midpoint,max-leaf=8 --force -o " + q("s.bvh"));
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(fs::file_size(path("s.bvh")), size_before);

    // A structure saved for one scene is refused for another.
    std::ofstream(path("tri.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    r = run_cli("trace " + q("tri.obj") + " --load " + q("s.bvh") + " --rays " + q("rays.npy") + " -o " +
                q("bad_hits.npy"));
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_FALSE(fs::exists(path("bad_hits.npy")));
}

// `thicket build --threads N` writes the same file for any N, on a scene big enough that the top
// of the tree is split by several threads together (kParallelNodeSize) and below it subtrees run
// as tasks.
TEST_F(CliTest, BuildWritesTheSameFileOnAnyNumberOfThreads) {
    std::ofstream obj(path("soup.obj"));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 100.0f), d(-0.5f, 0.5f);
    const int triangles = 40000;
    for (int t = 0; t < triangles; ++t) {
        const float x = u(rng), y = u(rng) * (t % 3 ? 1.0f : 0.1f), z = u(rng);
        obj << "v " << x << ' ' << y << ' ' << z << "\nv " << x + d(rng) << ' ' << y + d(rng) << ' ' << z
            << "\nv " << x << ' ' << y + d(rng) << ' ' << z + d(rng) << '\n';
    }
    for (int t = 0; t < triangles; ++t) obj << "f " << 3 * t + 1 << ' ' << 3 * t + 2 << ' ' << 3 * t + 3 << '\n';
    obj.close();
    for (const char* spec : {"bvh", "bvh:builder=sweep-sah,max-leaf=2"}) {
        std::string first;
        for (int threads : {1, 2, 5}) {
            const std::string out = path("t" + std::to_string(threads) + ".bvh");
            const RunResult r = run_cli("build " + q("soup.obj") + " --accel " + spec + " --threads " +
                                        std::to_string(threads) + " -o " + quote(out));
            ASSERT_EQ(r.code, 0) << r.output;
            std::ifstream in(out, std::ios::binary);
            const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
            ASSERT_GT(bytes.size(), size_t(triangles) * 4) << spec;
            if (first.empty())
                first = bytes;
            else
                EXPECT_TRUE(bytes == first) << spec << ": the file on " << threads << " threads differs from 1 thread's";
            fs::remove(out);
        }
    }
}

TEST_F(CliTest, InfoDescribesSceneAndStructure) {
    const RunResult r = run_cli("info cornell --accel bvh");
    ASSERT_EQ(r.code, 0) << r.output;
    for (const char* needle : {"triangles            36", "zero-area triangles  0", "bounds min", "materials",
                               "nodes", "leaves", "max depth", "bytes/primitive", "SAH cost", "C_trav = 1",
                               "build time"})
        EXPECT_NE(r.output.find(needle), std::string::npos) << needle << "\n" << r.output;
}

// Registered variants covering every option value, run through the CLI on Sponza, answer 10^5
// random rays like brute force (through a reference checked against it: see reference_for).
TEST_F(CliTest, SponzaEveryVariantAgreesWithBruteForce) {
    const std::string scene = std::string(THICKET_SHARED_SCENES) + "/sponza-dabrovic.ply";
    if (!fs::exists(scene))
        GTEST_SKIP() << "../shared/scenes was not found (looked for " << scene << "); real-scene CLI test skipped";
    const Scene sponza = load_scene(scene);
    const Aabb b = sponza.bounds();
    const Vec3 lo = b.min - b.extent() * 0.05f, hi = b.max + b.extent() * 0.05f;
    std::mt19937 rng(20240611);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<float> rows;
#if defined(THICKET_SANITIZED) || !defined(NDEBUG)
    // Unoptimised or instrumented brute force would take many minutes: fewer rays, same checks.
    const size_t count = 500;
#else
    const size_t count = 100000;
#endif
    for (size_t i = 0; i < count; ++i) {
        const Vec3 o{lo.x + (hi.x - lo.x) * unit(rng), lo.y + (hi.y - lo.y) * unit(rng), lo.z + (hi.z - lo.z) * unit(rng)};
        const float z = 2.0f * unit(rng) - 1.0f, phi = 6.2831853f * unit(rng), s = std::sqrt(std::max(0.0f, 1 - z * z));
        Vec3 d{s * std::cos(phi), s * std::sin(phi), z};
        if (i % 97 == 0) d = Vec3{0, 0, 0}, d[int(i / 97 % 3)] = (i & 1) ? 1.0f : -1.0f;  // axis-parallel
        const float tmax = i % 5 == 0 ? unit(rng) * 0.25f * length(b.extent()) : kInfinity;
        push_ray(rows, o, d, 0.0f, tmax);
    }
    write_npy_f32(path("rays.npy"), {count, 8}, rows);
    // The watertight test makes brute force several times slower (it ran 256 s against Moller's
    // 55 s on 10^5 rays), and it changes only the triangle test, which the conformance suite checks
    // on every structure: its variants answer the first fifth of the rays here.
    const size_t watertight_count = count / 5;
    write_npy_f32(path("rays-watertight.npy"), {watertight_count, 8},
                  std::vector<float>(rows.begin(), rows.begin() + std::ptrdiff_t(watertight_count * 8)));
    auto rays_file = [&](const std::string& isect) { return isect == "watertight" ? "rays-watertight.npy" : "rays.npy"; };
    auto ray_count = [&](const std::string& isect) { return isect == "watertight" ? watertight_count : count; };

    // Reference answers per triangle test. Brute force over all the rays cost a minute of CI per
    // triangle test, so the reference is the lecture's BVH through the CLI, itself checked against
    // in-process brute force on the first kBruteRays rays; where a variant disagrees with it, brute
    // force judges that ray alone (a wrong reference cannot pass a wrong variant there, nor fail a
    // right one). The any-hit reference is whether the closest hit exists (same triangle test,
    // same [tmin, tmax]).
    const size_t kBruteRays = std::min<size_t>(count, 3000);
    struct Reference {
        std::vector<Hit> hits;
        std::vector<uint8_t> any;
        std::unique_ptr<Accel> brute;
    };
    std::map<std::string, Reference> reference;
    auto brute_answer = [&](const Accel& brute, size_t i) {
        Ray ray;
        if (!make_ray(&rows[8 * i], ray)) return Hit{};
        const Hit h = brute.intersect(ray);
        return h.found() ? h : Hit{};
    };
    auto reference_for = [&](const std::string& isect) -> const Reference& {
        auto it = reference.find(isect);
        if (it != reference.end()) return it->second;
        const std::string spec = isect.empty() ? "bvh" : "bvh:isect=" + isect;
        const RunResult r = run_cli("trace " + quote(scene) + " --accel " + quote(spec) + " --rays " +
                                    q(rays_file(isect)) + " --force -o " + q("ref.npy"));
        EXPECT_EQ(r.code, 0) << r.output;
        Reference ref;
        ref.hits = read_npy_hits(path("ref.npy"));
        ref.brute = build_accel(isect.empty() ? "brute" : "brute:isect=" + isect, sponza);
        const thicket::testing::PrimitiveProbe probe(sponza, isect);
        const size_t checked = std::min(kBruteRays, ref.hits.size());
        size_t wrong = 0;
        for (size_t i = 0; i < checked; ++i)
            if (!agrees(ref.hits[i], brute_answer(*ref.brute, i), &rows[8 * i], probe) && ++wrong <= 5)
                ADD_FAILURE() << "reference " << spec << ": " << describe(rows, i, ref.hits[i], brute_answer(*ref.brute, i));
        EXPECT_EQ(wrong, 0u) << "the reference " << spec << " disagrees with brute force";
        std::printf("[ reference ] %s, checked against brute force on its first %zu rays\n", spec.c_str(), checked);
        ref.any.resize(ref.hits.size());
        for (size_t i = 0; i < ref.hits.size(); ++i) ref.any[i] = ref.hits[i].found() ? 1 : 0;
        return reference[isect] = std::move(ref);
    };

    // Release builds run the variants that cover every option value of every structure through
    // the CLI (the conformance suite runs the cross products in process); sanitized builds check
    // the CLI's own code with each structure's first variant. THICKET_FULL=1 runs them all.
    const char* full_env = std::getenv("THICKET_FULL");
    const bool every_variant = full_env && *full_env && std::string(full_env) != "0";
#ifdef THICKET_SANITIZED
    const bool first_of_each = !every_variant;
#else
    const bool first_of_each = false;
#endif
    const std::vector<std::string> variants =
        every_variant ? all_accel_variants() : thicket::testing::covering_variants(all_accel_variants());
    std::set<std::string> structures_seen;
    size_t tested = 0;
    for (const std::string& variant : variants) {
        const AccelSpec spec = parse_accel_spec(variant);
        if (spec.name == "brute") continue;  // the reference itself
        if (!structures_seen.insert(spec.name).second && first_of_each) continue;
        SCOPED_TRACE(variant);
        const std::string isect = spec.options.count("isect") ? spec.get("isect") : "";
        const Reference& ref = reference_for(isect);
        const std::vector<Hit>& want = ref.hits;
        const thicket::testing::PrimitiveProbe probe(sponza, isect);
        const size_t n = ray_count(isect);
        ASSERT_EQ(want.size(), n);

        RunResult r = run_cli("trace " + quote(scene) + " --accel " + quote(variant) + " --rays " + q(rays_file(isect)) +
                              " --force -o " + q("hits.npy"));
        ASSERT_EQ(r.code, 0) << r.output;
        const std::vector<Hit> got = read_npy_hits(path("hits.npy"));
        ASSERT_EQ(got.size(), n);
        size_t bad = 0, judged = 0;
        for (size_t i = 0; i < n; ++i) {
            if (agrees(got[i], want[i], &rows[8 * i], probe)) continue;
            ++judged;
            const Hit truth = brute_answer(*ref.brute, i);
            if (!agrees(got[i], truth, &rows[8 * i], probe) && ++bad <= 5) ADD_FAILURE() << describe(rows, i, got[i], truth);
        }
        EXPECT_EQ(bad, 0u);
        // Ties aside, variants answer like the reference: many rays judged by brute force would mean a
        // reference wrong beyond the checked prefix, which this test is not meant to lean on.
        EXPECT_LE(judged, n / 1000 + 5) << "rays where " << variant << " and the reference differed";

        r = run_cli("trace " + quote(scene) + " --any-hit --accel " + quote(variant) + " --rays " + q(rays_file(isect)) +
                    " --force -o " + q("any.npy"));
        ASSERT_EQ(r.code, 0) << r.output;
        const std::vector<uint8_t> got_any = read_npy_u8(path("any.npy"));
        ASSERT_EQ(got_any.size(), n);
        size_t bad_any = 0;
        for (size_t i = 0; i < n; ++i) {
            if (got_any[i] == ref.any[i]) continue;
            Ray ray;
            const uint8_t truth = make_ray(&rows[8 * i], ray) && ref.brute->occluded(ray) ? 1 : 0;
            if (got_any[i] != truth && ++bad_any <= 5)
                ADD_FAILURE() << "any-hit ray " << i << ": got " << int(got_any[i]) << ", brute force says " << int(truth);
        }
        EXPECT_EQ(bad_any, 0u);
        ++tested;
    }
    EXPECT_GT(tested, 0u);
}

namespace {

// Two closed boxes, [-1, 1]^3 and [-0.5, 0.5]^3, as an OBJ file: inside only between them.
void write_nested_boxes(const std::string& file) {
    std::ofstream out(file);
    for (float h : {1.0f, 0.5f})
        for (int k = 0; k < 8; ++k) out << "v " << (k & 1 ? h : -h) << ' ' << (k & 2 ? h : -h) << ' ' << (k & 4 ? h : -h) << '\n';
    const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5}, {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
    for (int base : {0, 8})
        for (const auto& f : faces) out << "f " << base + f[0] << ' ' << base + f[1] << ' ' << base + f[2] << ' ' << base + f[3] << '\n';
}

}  // namespace

TEST_F(CliTest, OccupancyAndSignedClosestAnswerAsTheLibraryForAnyStructure) {
    write_nested_boxes(path("boxes.obj"));
    const std::vector<float> points = {0, 0, 0, 0.75f, 0, 0, 0, -0.8f, 0.1f, 1.5f, 0, 0, 0.2f, 0.1f, -0.3f};
    const std::vector<uint8_t> want_inside = {0, 1, 1, 0, 0};
    write_npy_f32(path("points.npy"), {5, 3}, points);
    for (const char* accel : {"grid", "bvh8", "kdtree"}) {
        RunResult r = run_cli("occupancy " + q("boxes.obj") + " --accel " + accel + " --samples 5 -p " + q("points.npy") +
                              " -o " + q("inside.npy") + " --force");
        ASSERT_EQ(r.code, 0) << r.output;
        EXPECT_NE(r.output.find("inside  2 of 5 points"), std::string::npos) << r.output;
        EXPECT_EQ(read_npy_u8(path("inside.npy")), want_inside) << accel;
    }
    // closest --signed with a structure that answers no closest points itself: the bvh8 fallback.
    RunResult r = run_cli("closest " + q("boxes.obj") + " --accel grid --signed -p " + q("points.npy") + " -o " +
                          q("closest.npy"));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("a bvh8 over the same scene answers them"), std::string::npos) << r.output;
    std::ifstream in(path("closest.npy"), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(bytes.size(), 5u * 28);
    const char* records = bytes.data() + bytes.size() - 5 * 28;  // x y z distance prim u v, 28 bytes each
    const Scene scene = load_scene(path("boxes.obj"));
    const auto brute = build_accel("brute", scene);
    for (size_t i = 0; i < 5; ++i) {
        float distance;
        uint32_t prim;
        std::memcpy(&distance, records + 28 * i + 12, 4);
        std::memcpy(&prim, records + 28 * i + 16, 4);
        const NearestPoint want = brute->closest_point({points[3 * i], points[3 * i + 1], points[3 * i + 2]});
        EXPECT_EQ(prim, want.prim) << i;
        EXPECT_FLOAT_EQ(distance, want_inside[i] ? -want.distance : want.distance) << i;
    }
    r = run_cli("occupancy " + q("boxes.obj") + " --samples 4 -p " + q("points.npy") + " -o " + q("x.npy"));
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.output.find("nsamples must be odd"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(path("x.npy")));
}

}  // namespace cli_test
