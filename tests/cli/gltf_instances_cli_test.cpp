// glTF instancing through the `thicket` command: `info` counts the instances a shared mesh
// becomes, `--flatten` gives the triangle soup of before, render and trace take the instanced
// scene, and every subcommand that loads a scene accepts --flatten.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/cli_dir_test.h"
#include "support/gltf_instances_scene.h"
#include "thicket/util/npy.h"

namespace gltf_instances_cli_test {

namespace {

using thicket::testing::CliDirTest;

class GltfInstancesCli : public CliDirTest {
protected:
    void SetUp() override {
        CliDirTest::SetUp();
        if (IsSkipped()) return;
        write("scene.bin", thicket::testing::gltf_instances_buffer());
        write("scene.gltf", thicket::testing::gltf_instances_json("scene.bin"));
    }
};

TEST_F(GltfInstancesCli, InfoCountsInstancesAndFlattenGivesTheCopies) {
    const auto info = run("info " + q("scene.gltf") + " --no-accel");
    ASSERT_EQ(info.code, 0) << info.output;
    EXPECT_NE(info.output.find("geometries           2\n"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("instances            4, placing 2 of the geometries"), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("unique primitives    8 "), std::string::npos) << info.output;
    EXPECT_NE(info.output.find("instanced primitives 20 "), std::string::npos) << info.output;

    const auto flat = run("info --flatten " + q("scene.gltf") + " --no-accel");
    ASSERT_EQ(flat.code, 0) << flat.output;
    EXPECT_NE(flat.output.find("triangles            20\n"), std::string::npos) << flat.output;
    EXPECT_NE(flat.output.find("geometries           1\n"), std::string::npos) << flat.output;
    EXPECT_EQ(flat.output.find("instances "), std::string::npos) << flat.output;
}

TEST_F(GltfInstancesCli, RenderTraceAndClosestTakeTheInstancedScene) {
    const auto render = run("render " + q("scene.gltf") + " --size 16x12 -o " + q("out.png"));
    EXPECT_EQ(render.code, 0) << render.output;
    const auto rays = run("rays " + q("scene.gltf") + " --set primary --size 16x12 -o " + q("rays.npy"));
    ASSERT_EQ(rays.code, 0) << rays.output;
    const auto trace = run("trace " + q("scene.gltf") + " -r " + q("rays.npy") + " -o " + q("hits.npy"));
    EXPECT_EQ(trace.code, 0) << trace.output;
    // Closest points are answered over the flattened copy (no instanced walk answers them).
    thicket::write_npy_f32(path("points.npy"), {2, 3}, std::vector<float>{0.5f, 0.5f, 0.5f, 3.0f, 1.0f, -1.0f});
    const auto closest = run("closest " + q("scene.gltf") + " -p " + q("points.npy") + " -o " + q("closest.npy"));
    EXPECT_EQ(closest.code, 0) << closest.output;
    // Saving is refused with the way out named.
    const auto build = run("build " + q("scene.gltf") + " -a bvh -o " + q("scene.bvh"));
    EXPECT_EQ(build.code, 1) << build.output;
    EXPECT_NE(build.output.find("--flatten"), std::string::npos) << build.output;
    const auto flat = run("build --flatten " + q("scene.gltf") + " -a bvh -o " + q("scene.bvh"));
    EXPECT_EQ(flat.code, 0) << flat.output;
}

TEST_F(GltfInstancesCli, EverySceneLoadingCommandDocumentsFlatten) {
    for (const char* command : {"render", "trace", "closest", "occupancy", "info", "build", "rays", "bench", "compare",
                                "explore", "explain"}) {
        const auto help = run(std::string(command) + " --help");
        EXPECT_EQ(help.code, 0) << command << ": " << help.output;
        EXPECT_NE(help.output.find("--flatten"), std::string::npos) << command << ": " << help.output;
    }
    const auto top = run("--help");
    EXPECT_NE(top.output.find("--flatten"), std::string::npos) << top.output;
}

}  // namespace

}  // namespace gltf_instances_cli_test
