// The shared scenes are there: the one test that says so plainly (every real-scene test skips
// without them, and CI refuses skips: tests/ci/check_refuse_skips.sh shows it does).
#include <gtest/gtest.h>

#include "support/test_scenes.h"
#include "thicket/scene/scene.h"

namespace thicket::shared_scenes_test {
namespace {

TEST(SharedScenes, ArePresentAndLoad) {
    const std::vector<std::string> files = testing::shared_scene_files();
    if (files.empty()) GTEST_SKIP() << testing::shared_scenes_missing_message();
    for (const std::string& file : files) {
        if (file.find("dragon") != std::string::npos) continue;  // 871k triangles: the big tests load it
        EXPECT_GT(load_scene(file).primitive_count(), 0u) << file;
    }
}

}  // namespace
}  // namespace thicket::shared_scenes_test
