// `thicket trace` with float64 rays (issue 28): a precision=double bvh answers them as double
// brute force does, bit for bit, on the Cornell box moved 1e7 from the origin (where float's
// spacing is 1, wider than most of its triangles' features); a float structure refuses them,
// naming precision=double; `thicket closest` refuses float64 points, which no structure answers
// in double.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "support/cli_dir_test.h"
#include "thicket/core/vec3.h"
#include "thicket/scene/scene.h"
#include "thicket/scene/translate.h"

namespace double_rays_cli_test {

namespace fs = std::filesystem;

namespace {

constexpr double kOffset = 1e7;

/// A little-endian '<f8' .npy file of shape (rows, cols), written here so that the test shares no
/// code with the reader it checks.
std::string npy_f64(const std::vector<double>& values, size_t cols) {
    std::string header = "{'descr': '<f8', 'fortran_order': False, 'shape': (" +
                         std::to_string(values.size() / cols) + ", " + std::to_string(cols) + "), }";
    while ((10 + header.size() + 1) % 64 != 0) header += ' ';
    header += '\n';
    std::string out = "\x93NUMPY";
    out += char(1);
    out += char(0);
    out += char(header.size() & 0xff);
    out += char(header.size() >> 8);
    out += header;
    out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double));
    return out;
}

/// The data of a version 1 .npy file (its header skipped).
std::string npy_data(const std::string& file) {
    if (file.size() < 10) return "";
    const size_t header = size_t(uint8_t(file[8])) | size_t(uint8_t(file[9])) << 8;
    return file.substr(10 + header);
}

/// A trace record of float64 rays: t, prim, u, v (28 bytes, packed).
struct HitRecord {
    double t, u, v;
    uint32_t prim;
};

std::vector<HitRecord> hit_records(const std::string& file) {
    const std::string data = npy_data(file);
    std::vector<HitRecord> out(data.size() / 28);
    for (size_t i = 0; i < out.size(); ++i) {
        const char* r = data.data() + 28 * i;
        std::memcpy(&out[i].t, r, 8);
        std::memcpy(&out[i].prim, r + 8, 4);
        std::memcpy(&out[i].u, r + 12, 8);
        std::memcpy(&out[i].v, r + 20, 8);
    }
    return out;
}

class DoubleRaysCli : public thicket::testing::CliDirTest {
protected:
    void SetUp() override {
        CliDirTest::SetUp();
        if (IsSkipped()) return;
        // The Cornell box moved to 1e7 on every axis, written with its double coordinates.
        scene_ = thicket::translated_scene(thicket::load_scene("cornell"), kOffset);
        std::string ply = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(scene_.mesh.positions_double.size()) +
                          "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
                          std::to_string(scene_.mesh.triangle_count()) +
                          "\nproperty list uchar int vertex_indices\nend_header\n";
        char line[128];
        for (const thicket::Vec3d& p : scene_.mesh.positions_double) {
            std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
            ply += line;
        }
        for (size_t t = 0; t < scene_.mesh.triangle_count(); ++t)
            ply += "3 " + std::to_string(scene_.mesh.indices[3 * t]) + " " + std::to_string(scene_.mesh.indices[3 * t + 1]) +
                   " " + std::to_string(scene_.mesh.indices[3 * t + 2]) + "\n";
        write("far.ply", ply);
        // Rays from inside the box (every one hits a wall or a block) in random directions, some
        // with a short tmax; origins and directions in double, far from float's grid.
        std::mt19937 rng(28);
        std::uniform_real_distribution<double> unit(0.0, 1.0), dir(-1.0, 1.0);
        for (size_t i = 0; i < kRays; ++i) {
            const double tmax = i % 5 == 0 ? 0.3 : INFINITY;
            rays_.insert(rays_.end(), {kOffset + 0.05 + 0.9 * unit(rng), kOffset + 0.05 + 0.9 * unit(rng),
                                       kOffset - 0.05 - 0.9 * unit(rng), dir(rng), dir(rng), dir(rng), 0.0, tmax});
        }
        write("rays.npy", npy_f64(rays_, 8));
    }

    /// `thicket trace far.ply` with `accel` and `extra` options, writing `out`.
    thicket::testing::CliResult trace(const std::string& accel, const std::string& extra, const std::string& out) const {
        return run("trace " + q("far.ply") + " --accel " + accel + " --rays " + q("rays.npy") + " -o " + q(out) + " " +
                   extra);
    }

    static constexpr size_t kRays = 400;
    thicket::Scene scene_;
    std::vector<double> rays_;
};

TEST_F(DoubleRaysCli, DoubleBvhAnswersAsDoubleBruteForce) {
    for (const char* spec : {"bvh:precision=double", "brute:precision=double"}) {
        const auto r = trace(spec, "", std::string(spec).substr(0, 3) + ".npy");
        ASSERT_EQ(r.code, 0) << r.output;
        EXPECT_NE(r.output.find("traced in double"), std::string::npos) << r.output;
    }
    const std::string bvh = read("bvh.npy"), brute = read("bru.npy");
    ASSERT_FALSE(bvh.empty());
    EXPECT_NE(bvh.find("'<f8'"), std::string::npos) << "t, u and v are written as float64";
    EXPECT_EQ(npy_data(bvh), npy_data(brute)) << "every byte of every record";
    // Each hit lies on its triangle's plane to within double's rounding, with the ray's own double
    // origin: rays rounded to float on the way (1 unit apart here) would miss the plane by up to
    // a unit, which brute force and the BVH, given the same rounded rays, would agree on.
    const std::vector<HitRecord> hits = hit_records(bvh);
    ASSERT_EQ(hits.size(), kRays);
    size_t found = 0, off_plane = 0;
    std::string first_off;
    for (size_t i = 0; i < kRays; ++i) {
        if (hits[i].prim == 0xFFFFFFFFu) {
            EXPECT_TRUE(std::isinf(hits[i].t)) << "ray " << i;
            continue;
        }
        ++found;
        const double* r = &rays_[8 * i];
        const thicket::Vec3d p{r[0] + hits[i].t * r[3], r[1] + hits[i].t * r[4], r[2] + hits[i].t * r[5]};
        const thicket::Vec3d a = scene_.mesh.vertex_double(hits[i].prim, 0), b = scene_.mesh.vertex_double(hits[i].prim, 1),
                             c = scene_.mesh.vertex_double(hits[i].prim, 2);
        const thicket::Vec3d on = a + (b - a) * hits[i].u + (c - a) * hits[i].v;
        if (!(length(p - on) < 1e-6) && off_plane++ == 0)
            first_off = "ray " + std::to_string(i) + ": " + std::to_string(length(p - on)) + " off prim " +
                        std::to_string(hits[i].prim);
        EXPECT_LE(hits[i].t, r[7]) << "ray " << i;
    }
    EXPECT_EQ(off_plane, 0u) << first_off;
    EXPECT_GT(found, kRays / 2);

    // --count and --all: the crossings, found in double, agree too.
    for (const char* spec : {"bvh:precision=double", "brute:precision=double"}) {
        const std::string tag = std::string(spec).substr(0, 3);
        auto r = trace(spec, "--count", tag + "-count.npy");
        ASSERT_EQ(r.code, 0) << r.output;
        EXPECT_NE(r.output.find("in double"), std::string::npos) << r.output;
        r = trace(spec, "--all", tag + "-all.npy");
        ASSERT_EQ(r.code, 0) << r.output;
    }
    EXPECT_EQ(npy_data(read("bvh-count.npy")), npy_data(read("bru-count.npy")));
    EXPECT_EQ(read("bvh-all.npy"), read("bru-all.npy"));
    const std::string count_data = npy_data(read("bvh-count.npy"));
    std::vector<uint32_t> counts(count_data.size() / 4);
    std::memcpy(counts.data(), count_data.data(), count_data.size());
    ASSERT_EQ(counts.size(), kRays);
    uint64_t total = 0;
    for (size_t i = 0; i < kRays; ++i) {
        total += counts[i];
        // The closest hit is the first crossing: a ray has one exactly when it has a hit.
        EXPECT_EQ(counts[i] > 0, hits[i].prim != 0xFFFFFFFFu) << "ray " << i;
    }
    const std::string all = read("bvh-all.npy");
    EXPECT_NE(all.find("('t', '<f8')"), std::string::npos) << all.substr(0, 128);
    EXPECT_EQ(npy_data(all).size(), total * 32) << "one 32-byte record (ray, t, prim, u, v) per crossing";
}

TEST_F(DoubleRaysCli, FloatStructuresRefuseFloat64Rays) {
    for (const char* extra : {"", "--any-hit", "--count", "--all"}) {
        expect_refused(trace("bvh", extra, "float.npy"), {"float64", "precision=double", "rays.npy"});
        EXPECT_FALSE(fs::exists(path("float.npy"))) << extra;
    }
    expect_refused(trace("bvh8", "", "float.npy"), {"precision=double", "'bvh8'"});
    // No packet path in double: --coherent is refused, not ignored.
    expect_refused(trace("bvh:precision=double", "--coherent", "float.npy"),
                   {"--coherent does not apply here", "float64 rays"});
    // A saved structure is always float (precision=double is not saved).
    ASSERT_EQ(run("build " + q("far.ply") + " --accel bvh -o " + q("far.bvh")).code, 0);
    expect_refused(run("trace " + q("far.ply") + " --load " + q("far.bvh") + " --rays " + q("rays.npy") + " -o " +
                       q("float.npy")),
                   {"precision=double", "--load"});
    // Points have no double path: float64 ones are refused, not rounded, whatever the structure.
    write("points.npy", npy_f64({kOffset, kOffset, kOffset}, 3));
    for (const char* accel : {"bvh", "bvh:precision=double"})
        for (const char* command : {"closest", "occupancy"})
            expect_refused(run(std::string(command) + " " + q("far.ply") + " --accel " + accel + " --points " +
                               q("points.npy") + " -o " + q("p.npy")),
                           {"float64 points", "float32", "points.npy"});
    EXPECT_FALSE(fs::exists(path("p.npy")));
}

}  // namespace

}  // namespace double_rays_cli_test
