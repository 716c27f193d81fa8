// `thicket build` writes the same file in every process: each run is a new address space (ASLR),
// so bytes the build leaves uninitialised (a node's padding once held stack garbage with
// pointers in it) differ from run to run even where one process building twice would not see it.
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "support/cli_dir_test.h"
#include "thicket/accel/registry.h"

namespace thicket::testing::build_determinism_cli_test {
namespace {

/// A binary PLY of `count` small random triangles, every fourth degenerate (a point, a segment,
/// a duplicate of the previous one, in turn), and one on a NaN vertex.
std::string degenerate_ply(int count) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), small(-0.05f, 0.05f);
    std::vector<float> xyz;
    std::vector<int32_t> faces;
    for (int i = 0; i < count; ++i) {
        const int32_t v = int32_t(xyz.size() / 3);
        const float x = u(rng), y = u(rng), z = u(rng);
        for (int k = 0; k < 3; ++k) xyz.insert(xyz.end(), {x + small(rng), y + small(rng), z + small(rng)});
        switch (i % 12) {
        case 3: faces.insert(faces.end(), {v, v, v}); break;
        case 7: faces.insert(faces.end(), {v, v + 1, v}); break;
        case 11: faces.insert(faces.end(), faces.end() - 3, faces.end()); break;
        default: faces.insert(faces.end(), {v, v + 1, v + 2});
        }
    }
    xyz.insert(xyz.end(), {std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f});
    faces.insert(faces.end(), {int32_t(xyz.size() / 3 - 1), 0, 1});
    std::string out = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(xyz.size() / 3) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(faces.size() / 3) + "\nproperty list uchar int vertex_indices\nend_header\n";
    out.append(reinterpret_cast<const char*>(xyz.data()), xyz.size() * sizeof(float));
    for (size_t f = 0; f < faces.size(); f += 3) {
        out.push_back(char(3));
        out.append(reinterpret_cast<const char*>(&faces[f]), 3 * sizeof(int32_t));
    }
    return out;
}

class BuildDeterminismCli : public CliDirTest {};

TEST_F(BuildDeterminismCli, EverySavedStructureWritesTheSameFileInEveryRunAndOnAnyThreads) {
    write("scene.ply", degenerate_ply(3000));
    std::vector<std::string> specs;
    for (const AccelInfo& info : accel_registry())
        if (info.load && info.name != "tetra") specs.push_back(info.name);  // tetra records TetGen's time
    for (const std::string name : {"bvh", "bvh8"})
        for (const std::string builder : {"midpoint", "sweep-sah", "lbvh", "sbvh"})
            specs.push_back(name + ":builder=" + builder);
    for (const std::string quality : {"low", "high"}) specs.push_back("bvh8:quality=" + quality);
    ASSERT_GE(specs.size(), 18u);
    for (const std::string& spec : specs) {
        const CliResult first = run("build scene.ply -a " + spec + " -o first.bin -f -j 1");
        ASSERT_EQ(first.code, 0) << spec << ": " << first.output;
        const std::string bytes = read("first.bin");
        for (const int threads : {1, 2, 7}) {
            const CliResult r = run("build scene.ply -a " + spec + " -o again.bin -f -j " + std::to_string(threads));
            ASSERT_EQ(r.code, 0) << spec << ": " << r.output;
            const std::string again = read("again.bin");
            size_t differ = 0;
            for (size_t i = 0; i < std::min(bytes.size(), again.size()); ++i) differ += bytes[i] != again[i] ? 1 : 0;
            EXPECT_TRUE(bytes == again) << spec << " -j " << threads << ": " << bytes.size() << " and " << again.size()
                                        << " bytes, " << differ << " differ";
        }
    }
}

}  // namespace
}  // namespace thicket::testing::build_determinism_cli_test
