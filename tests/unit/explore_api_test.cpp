// `thicket explore`'s JSON handlers (tools/thicket/explore/explore_api.h) called directly: each
// answer against what the library says independently, and each refusal's status and message.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <random>

#include "explore_api.h"
#include "thicket/accel/registry.h"

namespace thicket::explore_api_test {
namespace {

using nlohmann::json;

Scene small_scene() {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), d(-0.1f, 0.1f);
    Scene s;
    s.name = "small";
    for (uint32_t t = 0; t < 120; ++t) {
        const Vec3 c{u(rng), u(rng), u(rng)};
        for (int k = 0; k < 3; ++k) s.mesh.positions.push_back(c + Vec3{d(rng), d(rng), d(rng)});
        s.mesh.indices.insert(s.mesh.indices.end(), {3 * t, 3 * t + 1, 3 * t + 2});
    }
    return s;
}

struct ExploreApi : ::testing::Test {
    Scene scene = small_scene();
    std::unique_ptr<Accel> bvh = build_accel("bvh", scene, 1), grid = build_accel("grid", scene, 1);
    const Accel* bvh_view = bvh.get();
    const Accel* grid_view = grid.get();
    std::unique_ptr<explore::Session> session;
    void SetUp() override {
        std::vector<std::unique_ptr<Accel>> accels;
        accels.push_back(std::move(bvh));
        accels.push_back(std::move(grid));
        session = std::make_unique<explore::Session>(small_scene(), std::move(accels));
    }
    json ok(const std::string& method, const std::string& path, const json& body = nullptr) {
        const explore::Response r = session->handle(method, path, body.is_null() ? "" : body.dump());
        EXPECT_EQ(r.status, 200) << path << ": " << r.body;
        return json::parse(r.body);
    }
    /// The refusal's status, and its message must contain `needle`.
    void refused(const std::string& path, const std::string& body, int status, const std::string& needle,
                 const std::string& method = "POST") {
        const explore::Response r = session->handle(method, path, body);
        EXPECT_EQ(r.status, status) << path << " " << body.substr(0, 80) << ": " << r.body;
        const json j = json::parse(r.body, nullptr, false);
        ASSERT_TRUE(j.is_object() && j.contains("error")) << r.body;
        EXPECT_NE(j["error"].get<std::string>().find(needle), std::string::npos) << j["error"] << " lacks " << needle;
    }
    static json view(uint32_t w, uint32_t h) {
        return {{"camera", {{"eye", {0.5, 0.5, -2.0}}, {"target", {0.5, 0.5, 0.5}}, {"up", {0, 1, 0}}, {"fov", 40}}},
                {"width", w}, {"height", h}};
    }
};

TEST_F(ExploreApi, SceneStatsAndMesh) {
    const json s = ok("GET", "/api/scene");
    EXPECT_EQ(s["triangles"], 120);
    EXPECT_EQ(s["structures"][0]["spec"], bvh_view->spec());
    EXPECT_EQ(s["structures"][1]["draws_nodes"], true);
    const json st = ok("GET", "/api/stats");
    EXPECT_EQ(st["structures"][0]["nodes"], bvh_view->stats().nodes);
    EXPECT_EQ(st["structures"][1]["leaves"], grid_view->stats().leaves);
    const explore::Response m = session->handle("GET", "/api/mesh", "");
    ASSERT_EQ(m.body.size(), 120u * 9 * sizeof(float));
    float last[3];
    std::memcpy(last, m.body.data() + m.body.size() - sizeof last, sizeof last);
    EXPECT_EQ(last[2], scene.mesh.vertex(119, 2).z);
}

TEST_F(ExploreApi, NodesByDepth) {
    const json root = ok("POST", "/api/nodes", {{"structure", 0}, {"depth", 0}});
    ASSERT_EQ(root["boxes"].size(), 1u);
    const Aabb b = bvh_view->bounds();
    EXPECT_EQ(root["boxes"][0]["box"], json({b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}));
    EXPECT_EQ(root["max_depth"], bvh_view->stats().max_depth);
    // Every node appears at exactly one depth.
    size_t total = 0;
    for (uint32_t d = 0; d <= root["max_depth"].get<uint32_t>(); ++d)
        total += ok("POST", "/api/nodes", {{"structure", bvh_view->spec()}, {"depth", d}})["count"].get<size_t>();
    EXPECT_EQ(total, bvh_view->stats().nodes);
    EXPECT_EQ(ok("POST", "/api/nodes", {{"structure", 1}})["count"], grid_view->stats().leaves);
}

TEST_F(ExploreApi, HeatmapCountsTheRealStructureOnAShardScale) {
    const json h = ok("POST", "/api/heatmap", [] { json v = view(9, 7); v["structures"] = {0, 1}; return v; }());
    explore::View v;
    v.eye = {0.5f, 0.5f, -2.0f};
    v.target = {0.5f, 0.5f, 0.5f};
    v.fov_deg = 40;
    v.width = 9;
    v.height = 7;
    uint64_t max = 0;
    for (int m = 0; m < 2; ++m) {
        const Accel& a = m ? *grid_view : *bvh_view;
        uint64_t own_max = 0;
        for (uint32_t y = 0; y < 7; ++y)
            for (uint32_t x = 0; x < 9; ++x) {
                RayCounters c;
                a.intersect(v.pixel_ray(x, y), c);
                EXPECT_EQ(h["maps"][m]["values"][y * 9 + x], c.nodes) << m << " " << x << "," << y;
                own_max = std::max(own_max, c.nodes);
            }
        EXPECT_EQ(h["maps"][m]["max"], own_max);
        max = std::max(max, own_max);
    }
    EXPECT_EQ(h["max"], max);
}

TEST_F(ExploreApi, PixelRayGoesThroughTheTargetAtTheCentre) {
    explore::View v;
    v.eye = {1, 2, 3};
    v.target = {4, -2, 3};
    v.width = 5;
    v.height = 3;
    const Ray r = v.pixel_ray(2, 1);
    const Vec3 want = normalize(v.target - v.eye);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(r.dir[a], want[a], 1e-6f);
    // Row 0 is the top: its ray leans towards up.
    EXPECT_GT(dot(v.pixel_ray(2, 0).dir, v.up), dot(r.dir, v.up));
}

// Off the centre (issue 45: a mirrored camera passed the test above). The page draws with
// three.js's camera: looking down -z with y up, x grows to the right of the image and y to its
// top. A pixel's ray goes through its centre on the image plane at distance 1, whose half height
// is tan(fov / 2) and half width that times the aspect ratio.
TEST_F(ExploreApi, OffCentrePixelRaysGoThroughTheirPixelsAsThePageDrawsThem) {
    explore::View v;
    v.eye = {0, 0, 0};
    v.target = {0, 0, -5};
    v.up = {0, 1, 0};
    v.fov_deg = 60;
    v.width = 8;
    v.height = 4;
    const float half_h = std::tan(30.0f * 3.14159265358979f / 180.0f), half_w = half_h * 2.0f;
    for (uint32_t y = 0; y < v.height; ++y)
        for (uint32_t x = 0; x < v.width; ++x) {
            const Vec3 want = normalize(Vec3((2.0f * (float(x) + 0.5f) / 8.0f - 1.0f) * half_w,
                                             (1.0f - 2.0f * (float(y) + 0.5f) / 4.0f) * half_h, -1.0f));
            const Ray r = v.pixel_ray(x, y);
            for (int a = 0; a < 3; ++a) EXPECT_NEAR(r.dir[a], want[a], 1e-6f) << "pixel " << x << "," << y;
        }
    EXPECT_GT(v.pixel_ray(7, 2).dir.x, 0.0f) << "the right column looks right, not mirrored";
    EXPECT_LT(v.pixel_ray(0, 2).dir.x, 0.0f);
}

TEST_F(ExploreApi, TraceIsExplainOfThePixelsRay) {
    json req = view(16, 16);
    req["x"] = 8;
    req["y"] = 8;
    req["structure"] = 1;
    json t = ok("POST", "/api/trace", req);
    explore::View v;
    v.eye = {0.5f, 0.5f, -2.0f};
    v.target = {0.5f, 0.5f, 0.5f};
    v.fov_deg = 40;
    v.width = v.height = 16;
    json e = json::parse(explore::explain_ray(*grid_view, scene, v.pixel_ray(8, 8)));
    t.erase("pixel");
    EXPECT_EQ(t, e);
    EXPECT_TRUE(e["detailed"].get<bool>());
    EXPECT_FALSE(e["steps"].empty());
}

// grid2 tests primitives through the grid's cell code (which records them) but walks its own
// levels (which do not): its trace must say "totals only", not list a partial walk as whole.
TEST_F(ExploreApi, PartialRecordingIsReportedAsTotalsOnly) {
    const std::unique_ptr<Accel> grid2 = build_accel("grid2", scene, 1);
    Ray ray;
    ray.org = {0.5f, 0.5f, -1.0f};
    ray.dir = {0.01f, 0.02f, 1.0f};
    const json e = json::parse(explore::explain_ray(*grid2, scene, ray));
    RayCounters plain;
    grid2->intersect(ray, plain);
    ASSERT_GT(plain.prims, 0u);
    EXPECT_FALSE(e["detailed"].get<bool>());
    EXPECT_TRUE(e["steps"].empty());
    EXPECT_EQ(e["prims"], plain.prims);
}

// The shadow query (explain --any-hit): bvh and grid list its steps, which end at the first
// primitive that blocks the ray; the answer and the totals are the counting path's.
TEST_F(ExploreApi, AnyHitIsRecordedStepByStep) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-0.2f, 1.2f);
    size_t blocked = 0;
    for (const Accel* a : {bvh_view, grid_view})
        for (int i = 0; i < 50; ++i) {
            Ray ray;
            ray.org = {u(rng), u(rng), -1.0f};
            ray.dir = normalize(Vec3{u(rng), u(rng), 3.0f} - ray.org);
            const json e = json::parse(explore::explain_ray(*a, scene, ray, true));
            RayCounters plain;
            const bool occluded = a->occluded(ray, plain);
            ASSERT_EQ(e["query"], "any");
            ASSERT_EQ(e["occluded"], occluded);
            ASSERT_TRUE(e["hit"].is_null());
            ASSERT_TRUE(e["detailed"].get<bool>());
            EXPECT_EQ(e["nodes"], plain.nodes);
            EXPECT_EQ(e["prims"], plain.prims);
            size_t prims = 0;
            for (const json& s : e["steps"]) prims += s["kind"] == "prim";
            EXPECT_EQ(prims, plain.prims);
            if (!occluded) continue;
            ++blocked;
            // The last primitive tested is the one that blocks: it alone of those listed is hit.
            ASSERT_EQ(e["steps"].back()["kind"], "prim");
            for (size_t k = 0; k < e["steps"].size(); ++k) {
                const json& s = e["steps"][k];
                if (s["kind"] != "prim") continue;
                const uint32_t p = s["id"];
                Scene one;
                for (int c = 0; c < 3; ++c) one.mesh.positions.push_back(scene.mesh.vertex(p, c));
                one.mesh.indices = {0, 1, 2};
                EXPECT_EQ(build_accel("brute", one)->occluded(ray), k + 1 == e["steps"].size()) << "primitive " << p;
            }
        }
    EXPECT_GT(blocked, 10u);
    // The closest-hit form says so too.
    Ray ray;
    ray.org = {0.5f, 0.5f, -1.0f};
    ray.dir = {0.0f, 0.0f, 1.0f};
    EXPECT_EQ(json::parse(explore::explain_ray(*bvh_view, scene, ray))["query"], "closest");
}

// tetra's walk is recorded: its steps name tetrahedra, each with its four corners.
TEST_F(ExploreApi, TetraTraceListsTheWalkedTetrahedra) {
    const std::unique_ptr<Accel> tetra = build_accel("tetra", scene, 1);
    Ray ray;
    ray.org = {0.5f, 0.5f, -1.0f};
    ray.dir = normalize(Vec3{0.01f, 0.02f, 1.0f});
    const json e = json::parse(explore::explain_ray(*tetra, scene, ray));
    ASSERT_TRUE(e["detailed"].get<bool>());
    size_t entered = 0;
    for (const json& s : e["steps"])
        if (s["kind"] == "enter") {
            ++entered;
            ASSERT_EQ(s["tetrahedron"].size(), 4u);
            ASSERT_FALSE(s.contains("box"));
        }
    EXPECT_GT(entered, 1u);
}

TEST_F(ExploreApi, RefusalsNameWhatIsWrong) {
    refused("/api/nodes", "{not json", 400, "not JSON");
    refused("/api/nodes", "[1,2]", 400, "JSON object");
    refused("/api/nodes", R"({"structure":"octree"})", 404, "unknown structure \"octree\"");
    refused("/api/nodes", R"({"structure":7})", 404, "0 (bvh");
    refused("/api/nodes", R"({"structure":-1})", 404, "unknown structure -1");
    refused("/api/nodes", R"({"depth":100000})", 400, "\"depth\" = 100000 is out of range [0, 1000]");
    refused("/api/nodes", R"({"depth":1.5})", 400, "\"depth\" must be a whole number");
    refused("/api/nodes", R"({"depth":18446744073709551615})", 400, "out of range");
    refused("/api/heatmap", "{}", 400, "missing object \"camera\"");
    json v = view(0, 5);
    refused("/api/heatmap", v.dump(), 400, "\"width\" = 0 is out of range [1, 1024]");
    v = view(1024, 1024);
    refused("/api/heatmap", v.dump(), 400, "at most 262144");
    v = view(4, 4);
    v["metric"] = "time";
    refused("/api/heatmap", v.dump(), 400, "\"metric\" must be");
    v = view(4, 4);
    v["structures"] = {0, 1, 0};
    refused("/api/heatmap", v.dump(), 400, "1 or 2 structures");
    v = view(4, 4);
    v["camera"]["eye"] = {0.5, 0.5, 0.5};
    refused("/api/heatmap", v.dump(), 400, "distinct points");
    v = view(4, 4);
    v["camera"]["eye"] = {1e300, 0, 0};
    refused("/api/heatmap", v.dump(), 400, "finite numbers");
    v = view(4, 4);
    v["camera"]["up"] = {0, 0, 1};
    refused("/api/heatmap", v.dump(), 400, "parallel");
    v = view(4, 4);
    v["x"] = 4;
    v["y"] = 0;
    refused("/api/trace", v.dump(), 400, "\"x\" = 4 is out of range [0, 3]");
    v.erase("y");
    v["x"] = 0;
    refused("/api/trace", v.dump(), 400, "missing field \"y\"");
    refused("/api/nodes", std::string(explore::kMaxBodyBytes + 1, ' '), 413, "at most 65536");
    refused("/api/nodes", "", 405, "takes POST", "GET");
    refused("/api/nothing", "", 404, "no such request");
    // A structure that does not draw itself is told apart from a bad request.
    std::vector<std::unique_ptr<Accel>> one;
    one.push_back(build_accel("brute", scene, 1));
    const explore::Session brute(small_scene(), std::move(one));
    const explore::Response r = brute.handle("POST", "/api/nodes", "{}");
    EXPECT_EQ(r.status, 422);
    EXPECT_NE(r.body.find("does not draw its nodes"), std::string::npos);
}

}  // namespace
}  // namespace thicket::explore_api_test
