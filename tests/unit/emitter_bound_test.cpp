// Emitters and the renderer: an emitter at the material table's bound renders finite light, one
// beyond it is refused with the material's name instead of blacking the image out, light
// selection's total power stays finite, an emitter LightSet cannot sample is reported once, and a
// scene with no light gets a point light sized by what the camera sees (not by the scene's bounds).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/render/integrator.h"
#include "thicket/render/lights.h"
#include "thicket/render/render_scene.h"
#include "thicket/render/sampling.h"
#include "thicket/scene/material_ranges.h"
#include "thicket/scene/scene.h"

namespace thicket::emitter_bound_test {
namespace {

/// A floor quad (y = 0, facing up) and a lamp quad above it (y = 2, facing down).
TriangleMesh floor_and_lamp(Vec3 lamp_emission) {
    TriangleMesh m;
    m.positions = {{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2},
                   {-0.5f, 2, -0.5f}, {0.5f, 2, -0.5f}, {0.5f, 2, 0.5f}, {-0.5f, 2, 0.5f}};
    m.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    Material floor;
    floor.name = "floor";
    floor.diffuse = Vec3{0.5f};
    Material lamp;
    lamp.name = "lamp";
    lamp.diffuse = Vec3{0.0f};
    lamp.emission = lamp_emission;
    m.materials = {floor, lamp};
    m.material_ids = {0, 0, 1, 1};
    return m;
}

TraceOptions small_render(int w, int h, uint32_t spp) {
    TraceOptions o;
    o.width = w;
    o.height = h;
    o.spp = spp;
    o.progress = false;
    o.threads = 1;
    return o;
}

TEST(EmitterBound, EmitterAtTheBoundRendersFiniteAndNotBlack) {
    Scene scene;
    scene.add_mesh(floor_and_lamp(Vec3{float(kMaxEmission)}));
    const RenderScene rs = make_render_scene(scene);
    const LightSet lights(rs);
    ASSERT_EQ(lights.size(), 2u);
    EXPECT_TRUE(std::isfinite(lights.total_power()));
    const auto accel = build_accel("bvh", scene);
    const Camera camera({0, 1, 4}, {0, 0, 0});
    for (Integrator integrator : {Integrator::Path, Integrator::Whitted}) {
        const TraceResult r = trace_image(rs, *accel, camera, integrator, small_render(16, 16, 4));
        size_t lit = 0;
        for (const Vec3& c : r.radiance) {
            ASSERT_TRUE(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z));
            lit += luminance(c) > 0.0f;
        }
        // The floor fills the lower part of the view; every floor pixel is lit by the lamp.
        EXPECT_GT(lit, r.radiance.size() / 3) << integrator_name(integrator);
    }
}

TEST(EmitterBound, EmitterBeyondTheBoundIsRefusedByName) {
    Scene scene;
    const float inf = std::numeric_limits<float>::infinity();
    for (Vec3 e : {Vec3{inf, 1, 1}, Vec3{std::numeric_limits<float>::max(), 1, 1}, Vec3{float(2 * kMaxEmission), 0, 0},
                   Vec3{std::nanf(""), 1, 1}, Vec3{-1, 1, 1}}) {
        // A Material made in code: make_render_scene holds it to the table.
        Scene s;
        s.add_mesh(floor_and_lamp(e));
        try {
            make_render_scene(s);
            ADD_FAILURE() << "accepted emission " << e.x;
        } catch (const Error& err) {
            EXPECT_EQ(std::string(err.what()).rfind("render: material 'lamp': Ke[0]: must be a number from 0 to 1e+06", 0), 0u)
                << err.what();
        }
    }
    // A SurfaceMaterial made in code: the renderer refuses it before tracing (it used to turn
    // the light-selection total infinite and every lit pixel black).
    scene.add_mesh(floor_and_lamp(Vec3{1}));
    RenderScene rs = make_render_scene(scene);
    rs.materials.back().emission = Vec3{inf, 1, 1};
    const auto accel = build_accel("bvh", scene);
    for (Integrator integrator : {Integrator::Path, Integrator::Whitted}) {
        try {
            trace_image(rs, *accel, Camera({0, 1, 4}, {0, 0, 0}), integrator, small_render(4, 4, 1));
            ADD_FAILURE() << "rendered an infinite emitter";
        } catch (const Error& err) {
            EXPECT_NE(std::string(err.what()).find("material 'lamp': emission[0]: must be a number from 0 to 1e+06"),
                      std::string::npos)
                << err.what();
        }
    }
    EXPECT_THROW(LightSet{rs}, Error);
    rs.materials.back().emission = Vec3{1};
    rs.point_lights.push_back({{0, 1, 0}, Vec3{inf}});
    EXPECT_THROW(LightSet{rs}, Error);
}

// Float coordinates whose differences overflow float: the triangle's area (and with it the total
// power) is computed in double, so it stays finite at the emission bound.
TEST(EmitterBound, TotalPowerIsFiniteForTheLargestTriangles) {
    TriangleMesh m;
    m.positions = {{-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 3e38f, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    m.indices = {0, 1, 2, 3, 4, 5};
    Material lamp;
    lamp.name = "huge";
    lamp.emission = Vec3{float(kMaxEmission)};
    m.materials = {lamp};
    m.material_ids = {0, 0};
    Scene scene;
    scene.add_mesh(m);
    const RenderScene rs = make_render_scene(scene);
    const LightSet lights(rs);
    EXPECT_EQ(lights.size(), 2u);
    EXPECT_TRUE(std::isfinite(lights.total_power())) << lights.total_power();
    EXPECT_GT(lights.total_power(), 1e80);
}

TEST(EmitterBound, UnsampledEmissiveShapeIsReportedOnce) {
    Scene scene;
    scene.add_shape(Torus{{0, 0, 0}, {0, 1, 0}, 1.0f, 0.25f});
    RenderScene rs;
    rs.scene = &scene;
    SurfaceMaterial glow = lambert(Vec3{0.5f}, Vec3{2.0f});
    glow.name = "unsampled-ring-of-this-test";
    rs.materials = {lambert(Vec3{0.8f}), glow};
    rs.prim_material = {1};
    ::testing::internal::CaptureStderr();
    const LightSet first(rs), second(rs);
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_TRUE(first.empty());
    const std::string line = "render: material 'unsampled-ring-of-this-test' emits on a torus";
    const size_t at = err.find(line);
    ASSERT_NE(at, std::string::npos) << err;
    EXPECT_EQ(err.find(line, at + 1), std::string::npos) << "said twice: " << err;
}

/// The scene: a ground sphere of radius 1000 (the scene's bounds reach 2000 units down),
/// a unit sphere and a torus, no light, the camera a few units away.
struct GroundScene {
    Scene scene;
    GroundScene() {
        scene.add_shape(Sphere{{0, -1000, 0}, 1000});
        scene.add_shape(Sphere{{0, 1, 0}, 1});
        scene.add_shape(Torus{{2, 0.3f, 1.5f}, {0, 1, 0}, 0.6f, 0.25f});
    }
};

TEST(AutomaticLight, NoLightSceneIsLitWithoutSaturating) {
    const GroundScene g;
    RenderScene rs = make_render_scene(g.scene);
    const auto accel = build_accel("bvh", g.scene);
    const Camera camera({0, 2.6f, 8}, {0, 0.8f, 0}, {0, 1, 0}, 40);
    const int w = 48, h = 32;
    ::testing::internal::CaptureStderr();
    const std::string said = add_automatic_light(rs, *accel, camera, w, h);
    const std::string err = ::testing::internal::GetCapturedStderr();
    ASSERT_EQ(rs.point_lights.size(), 1u);
    EXPECT_NE(said.find("no light: added a point light at the camera"), std::string::npos) << said;
    EXPECT_NE(err.find(said), std::string::npos) << "not on stderr: " << err;
    // The old rule, 2 x (distance to the bounds' centre)^2, gave 2e6 here.
    EXPECT_LT(rs.point_lights[0].intensity.x, 1000.0f);

    const TraceResult r = trace_image(rs, *accel, camera, Integrator::Path, small_render(w, h, 4));
    size_t saturated = 0, lit = 0;
    for (const Vec3& c : r.radiance) {
        saturated += max_component(c) >= 1.0f;
        lit += luminance(c) > 0.02f;
    }
    const size_t n = r.radiance.size();
    EXPECT_LE(saturated, n / 20) << saturated << " of " << n << " pixels saturated";
    EXPECT_GE(lit, n / 3) << "only " << lit << " of " << n << " pixels lit";
}

TEST(AutomaticLight, SceneWithALightIsLeftAlone) {
    Scene scene;
    scene.add_mesh(floor_and_lamp(Vec3{5}));
    RenderScene rs = make_render_scene(scene);
    const auto accel = build_accel("bvh", scene);
    EXPECT_EQ(add_automatic_light(rs, *accel, Camera({0, 1, 4}, {0, 0, 0}), 8, 8), "");
    EXPECT_TRUE(rs.point_lights.empty());
    // Nothing visible: the distance falls back to the bounds' centre, still a finite light.
    const GroundScene g;
    RenderScene away = make_render_scene(g.scene);
    const auto ground_accel = build_accel("bvh", g.scene);
    ::testing::internal::CaptureStderr();
    add_automatic_light(away, *ground_accel, Camera({0, 5000, 0}, {0, 6000, 1}), 8, 8);
    ::testing::internal::GetCapturedStderr();
    ASSERT_EQ(away.point_lights.size(), 1u);
    EXPECT_TRUE(std::isfinite(away.point_lights[0].intensity.x));
}

}  // namespace
}  // namespace thicket::emitter_bound_test
