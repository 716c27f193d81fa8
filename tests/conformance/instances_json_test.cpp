// JSON scenes' "instances" (docs/shapes.md, "Instances"): geometry references and transforms
// (3x4 and 4x4), what build_accel, bounds() and normal() make of them, and every class of bad
// input, each message naming the file and the JSON path.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "support/temp_dir.h"
#include "thicket/instances/instances.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/scene/scene.h"

namespace thicket::instances_json_test {
namespace {

class TempDir : public testing::TempDir {
public:
    TempDir() : testing::TempDir("thicket_json_instances") {
        file("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    }
};

const char* kShapes = R"("shapes": [{"type": "mesh", "file": "quad.obj"},
                                    {"type": "sphere", "center": [0, 0, 0], "radius": 1}])";

std::string scene_with(const std::string& instances) {
    return std::string("{") + kShapes + R"(, "instances": )" + instances + "}";
}

void expect_error(const TempDir& tmp, const std::string& json, const std::vector<std::string>& fragments) {
    const std::string path = tmp.file("scene.json", json);
    try {
        load_scene(path);
        ADD_FAILURE() << "no error for " << json;
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(path, 0), 0u) << what;
        for (const std::string& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
    }
}

TEST(JsonInstances, PlaceGeometriesUnderTransforms) {
    TempDir tmp;
    const Scene s = load_scene(tmp.file("scene.json", scene_with(R"([
        {"shape": 0, "transform": [1,0,0,10, 0,1,0,0, 0,0,1,0]},
        {"shape": 0, "transform": [-2,0,0,0, 0,2,0,0, 0,0,2,5, 0,0,0,1]},
        {"shape": 1, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,-20]}])")));
    ASSERT_EQ(s.instances.size(), 3u);
    EXPECT_EQ(s.instances[1].geometry, 0u);
    EXPECT_EQ(s.instances[2].geometry, 1u);
    EXPECT_EQ(s.instances[1].transform.m[2][3], 5.0f);
    EXPECT_EQ(s.instanced_primitive_count(), 2u + 2u + 1u);
    // The prototypes are drawn only through the instances: the quad at x in [10, 11], the mirrored
    // one at x in [-2, 0], z = 5, the sphere around z = -20.
    const Aabb b = s.bounds();
    EXPECT_NEAR(b.min.x, -2.0f, 1e-4f);
    EXPECT_NEAR(b.max.x, 11.0f, 1e-4f);
    EXPECT_NEAR(b.min.z, -21.0f, 1e-4f);
    const auto accel = build_accel("bvh", s);
    // Down -z onto the mirrored quad at (-1, 1, 5): its flattened ids are 2 and 3.
    const Ray down{{-1.0f, 1.0f, 9.0f}, 0.0f, {0.0f, 0.0f, -1.0f}};
    const Hit h = accel->intersect(down);
    ASSERT_TRUE(h.found());
    EXPECT_NEAR(h.t, 4.0f, 1e-5f);
    EXPECT_TRUE(h.prim == 2 || h.prim == 3) << h.prim;
    // The quad faces +z (counter-clockwise seen from +z); mirrored in x it faces -z.
    EXPECT_NEAR(s.normal(down, h).z, -1.0f, 1e-6f);
    // Through the sphere instance at z = -20 along +z from z = -30: t = 9, flattened id 4.
    const Ray up{{0.0f, 0.0f, -30.0f}, 0.0f, {0.0f, 0.0f, 1.0f}};
    const Hit hs = accel->intersect(up);
    EXPECT_EQ(hs.prim, 4u);
    EXPECT_NEAR(hs.t, 9.0f, 1e-4f);
    EXPECT_NEAR(s.normal(up, hs).z, -1.0f, 1e-5f);
    // The prototype quad at the origin is not part of the scene.
    EXPECT_FALSE(accel->occluded(Ray{{0.5f, 0.5f, 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, 2.0f}));
}

TEST(JsonInstances, BadInstancesNameTheJsonPath) {
    TempDir tmp;
    expect_error(tmp, scene_with("{}"), {"instances: must be an array"});
    expect_error(tmp, scene_with("[3]"), {"instances[0]: must be an object"});
    expect_error(tmp, scene_with(R"([{"transform": [1,0,0,0, 0,1,0,0, 0,0,1,0]}])"), {"instances[0]: missing 'shape'"});
    expect_error(tmp, scene_with(R"([{"shape": 0}])"), {"instances[0]: missing 'transform'"});
    expect_error(tmp, scene_with(R"([{"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0], "scale": 2}])"),
                 {"instances[0]: unknown key 'scale'"});
    expect_error(tmp, scene_with(R"([{"shape": 2, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0]}])"),
                 {"instances[0].shape: must be the index of an entry of 'shapes' (0 to 1), got 2"});
    expect_error(tmp, scene_with(R"([{"shape": -1, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0]}])"),
                 {"instances[0].shape"});
    expect_error(tmp, scene_with(R"([{"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1]}])"),
                 {"instances[0].transform: must be an array of 12 numbers"});
    expect_error(tmp, scene_with(R"([{"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,"x"]}])"),
                 {"instances[0].transform[11]: must be an array of 12 numbers"});
    expect_error(tmp, scene_with(R"([{"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,1e300]}])"),
                 {"instances[0].transform[11]: must be a finite number"});
    expect_error(tmp, scene_with(R"([{"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,1,1]}])"),
                 {"instances[0].transform: the last row of a 4x4 transform must be 0 0 0 1"});
    expect_error(tmp,
                 scene_with(R"([{"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0]},
                                {"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1e-6,0]}])"),
                 {"instances[1].transform: the transform is singular or nearly so", "the limit is 10000"});
}

TEST(JsonInstances, InstancedStructureReportsWhatItHolds) {
    TempDir tmp;
    const Scene s = load_scene(tmp.file("scene.json", scene_with(R"([
        {"shape": 0, "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0]},
        {"shape": 0, "transform": [1,0,0,3, 0,1,0,0, 0,0,1,0]}])")));
    const auto accel = build_accel("bvh8", s);
    EXPECT_EQ(accel->spec(), parse_accel_spec("bvh8").str());
    const AccelStats st = accel->stats();
    EXPECT_EQ(st.primitives, 4u);
    bool instanced = false;
    for (const auto& [key, value] : st.extra) instanced = instanced || (key == "instances" && value == "2");
    EXPECT_TRUE(instanced);
    // Refit of an instanced structure is refused with a message saying what to do instead.
    try {
        accel->refit(s);
        ADD_FAILURE() << "refit accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("set_transform"), std::string::npos) << e.what();
    }
    const auto* two = dynamic_cast<const InstancedAccel*>(accel.get());
    ASSERT_NE(two, nullptr);
    const InstanceHit where = two->locate(3);
    EXPECT_EQ(where.instance, 1u);
    EXPECT_EQ(where.geometry, 0u);
    EXPECT_EQ(where.prim, 1u);
    EXPECT_EQ(two->locate(4).instance, kNoPrim);
}

}  // namespace
}  // namespace thicket::instances_json_test
