// The renderer's part of a JSON scene: named materials given to shapes, point lights, camera, and
// errors that name the key.
#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/render/integrator.h"
#include "thicket/render/render_json.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::render_json_test {
namespace {

TEST(RenderJson, MaterialsLightsAndCameraReachTheRenderScene) {
    const testing::TempDir dir("thicket_render_json");
    const std::string path = dir.file("s.json", R"({
      "materials": {"glass": {"ni": 1.5, "d": 0}, "lamp": {"kd": 0, "ke": [4, 4, 4], "two_sided": true},
                    "shiny": {"kd": 0.2, "ks": 0.5, "ns": 40}},
      "shapes": [
        {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass"},
        {"type": "teapot-patches"},
        {"type": "sphere", "center": [0, 5, 0], "radius": 0.5, "material": "lamp"},
        {"type": "torus", "center": [3, 0, 0], "major_radius": 1, "minor_radius": 0.25, "material": "shiny"}
      ],
      "lights": [{"type": "point", "position": [0, 10, 0], "intensity": 50}],
      "camera": {"position": [0, 2, 8], "target": [0, 0, 0], "fov": 40}
    })");
    std::vector<uint32_t> entry_prims;
    const Scene scene = load_json_scene(path, entry_prims);
    ASSERT_EQ(entry_prims.size(), 5u);
    RenderScene rs = make_render_scene(scene);
    apply_json_render_settings(path, rs);
    EXPECT_EQ(rs.material(0).kind, SurfaceKind::Dielectric);
    EXPECT_FLOAT_EQ(rs.material(0).ior, 1.5f);
    for (uint32_t p = entry_prims[1]; p < entry_prims[2]; ++p)
        EXPECT_EQ(rs.prim_material[p], 0u) << "the teapot keeps the default";
    EXPECT_TRUE(rs.material(entry_prims[2]).emissive());
    EXPECT_TRUE(rs.material(entry_prims[2]).two_sided);
    EXPECT_EQ(rs.material(entry_prims[3]).kind, SurfaceKind::Glossy);
    ASSERT_EQ(rs.point_lights.size(), 1u);
    EXPECT_EQ(rs.point_lights[0].intensity, Vec3{50.0f});
    ASSERT_TRUE(rs.camera.has_value());
    EXPECT_FLOAT_EQ(rs.camera->fov_degrees(), 40.0f);
    // And it renders: the lamp and the point light light the scene.
    const auto accel = build_accel("bvh", scene);
    TraceOptions o;
    o.width = o.height = 16;
    o.spp = 2;
    o.progress = false;
    const TraceResult r = trace_path(rs, *accel, *rs.camera, o);
    double sum = 0;
    for (const Vec3& c : r.radiance) sum += c.x + c.y + c.z;
    EXPECT_GT(sum, 0.0);
}

TEST(RenderJson, ErrorsNameTheKey) {
    const testing::TempDir dir("thicket_render_json");
    struct Case {
        const char* text;
        const char* needle;
    };
    const Case cases[] = {
        {R"({"shapes": [{"type": "sphere", "center": [0,0,0], "radius": 1, "material": "nope"}]})", "nope"},
        {R"({"materials": {"a": {"kd": [1, 2]}}, "shapes": []})", "materials.a.kd"},
        {R"({"materials": {"a": {"colour": 1}}, "shapes": []})", "colour"},
        {R"({"lights": [{"type": "spot", "position": [0,0,0]}], "shapes": []})", "lights[0].type"},
        {R"({"camera": {"position": [0,0,0], "target": [0,0,0]}, "shapes": []})", "camera"},
    };
    for (const Case& c : cases) {
        const std::string path = dir.file("bad.json", c.text);
        const Scene scene = load_scene(path);
        RenderScene rs = make_render_scene(scene);
        try {
            apply_json_render_settings(path, rs);
            ADD_FAILURE() << "accepted " << c.text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(c.needle), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace thicket::render_json_test
