// The preview renderer: camera geometry, auto framing, PNG output, the three views and the
// heatmap legend; plus parallel_for and Progress, which the renderer runs on.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "support/png_read.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/render/views.h"
#include "thicket/util/parallel.h"
#include "thicket/util/progress.h"

namespace render_test {


namespace fs = std::filesystem;
using namespace thicket;

namespace {

void expect_near_vec(Vec3 a, Vec3 b, float tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

// Two axis-aligned quads facing +z: the left one at z = 0, the right one at z = -1.
Scene two_quads() {
    Scene s;
    s.name = "two-quads";
    s.mesh.positions = {{-2, -1, 0}, {0, -1, 0}, {0, 1, 0}, {-2, 1, 0},
                        {0, -1, -1}, {2, -1, -1}, {2, 1, -1}, {0, 1, -1}};
    s.mesh.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    return s;
}

// Reports a work count that grows from left to right across the image, so heatmaps have a
// known maximum without depending on any real structure.
class FakeAccel : public Accel {
public:
    Aabb bounds() const override { return {}; }
    Hit intersect(const Ray& ray) const override { return miss_for(ray); }
    Hit intersect(const Ray& ray, RayCounters& c) const override {
        c.nodes += uint64_t(std::lround((ray.dir.x + 1.0f) * 50.0f));
        c.prims += 2;
        return miss_for(ray);
    }
    bool occluded(const Ray&) const override { return false; }
    bool occluded(const Ray&, RayCounters&) const override { return false; }
    AccelStats stats() const override { return {}; }
};

bool is_grey(Rgb8 c) { return c.r == c.g && c.g == c.b; }
float luma(Vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

}  // namespace

TEST(Camera, CentreRayPointsAtTheTarget) {
    const Camera cam({1, 2, 3}, {-4, 0.5f, 7}, {0, 1, 0}, 60);
    const Ray r = cam.generate(320, 240, 640, 480);
    expect_near_vec(r.org, {1, 2, 3}, 0);
    expect_near_vec(r.dir, normalize(Vec3{-4, 0.5f, 7} - Vec3{1, 2, 3}), 1e-6f);
    EXPECT_NEAR(length(r.dir), 1.0f, 1e-6f);
    EXPECT_EQ(r.tmin, 0.0f);
    EXPECT_TRUE(std::isinf(r.tmax));
}

TEST(Camera, ImageAxesAndFieldOfView) {
    const Camera cam({0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 90);
    // Top-left corner: up and to the left; at the top edge's middle the ray is 45 degrees up.
    const Ray tl = cam.generate(0, 0, 200, 100);
    EXPECT_LT(tl.dir.x, 0.0f);
    EXPECT_GT(tl.dir.y, 0.0f);
    const Ray top = cam.generate(100, 0, 200, 100);
    EXPECT_NEAR(top.dir.y, -top.dir.z, 1e-6f);
    // Horizontal extent follows the aspect ratio: the right edge is at tan = 2.
    const Ray right = cam.generate(200, 50, 200, 100);
    EXPECT_NEAR(right.dir.x / -right.dir.z, 2.0f, 1e-5f);
}

TEST(Camera, ProjectInvertsGenerate) {
    const Camera cam({3, 1, -2}, {0, 0.5f, 0.25f}, {0, 1, 0}, 40);
    for (float px : {0.5f, 100.0f, 639.5f})
        for (float py : {0.5f, 240.0f, 479.0f}) {
            const Ray r = cam.generate(px, py, 640, 480);
            float qx = -1, qy = -1;
            ASSERT_TRUE(cam.project(r.org + r.dir * 7.0f, 640, 480, qx, qy));
            EXPECT_NEAR(qx, px, 1e-2f);
            EXPECT_NEAR(qy, py, 1e-2f);
        }
    float qx, qy;
    EXPECT_FALSE(cam.project({6, 1.5f, -4.5f}, 640, 480, qx, qy)) << "a point behind the camera";
}

TEST(Camera, LookingStraightDownStillHasAnUpVector) {
    const Camera cam({0, 10, 0}, {0, 0, 0});
    EXPECT_NEAR(length(cam.right()), 1.0f, 1e-6f);
    EXPECT_NEAR(length(cam.up()), 1.0f, 1e-6f);
    EXPECT_NEAR(dot(cam.up(), cam.forward()), 0.0f, 1e-6f);
    EXPECT_THROW(Camera({1, 1, 1}, {1, 1, 1}), Error);
    EXPECT_THROW(Camera({0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 180), Error);
}

// Issue 31: a target at 1e20 squared to inf in the normalisation, leaving a zero forward vector
// and NaN rays. The far target now gives exactly the view of a near one on the same line, and a
// view direction that itself passes float's range is refused naming the points.
TEST(Camera, FarTargetsKeepTheirDirection) {
    const Camera near({0, 1, 3.5f}, {0, 1, 0}), far({0, 1, 3.5f}, {0, 1, -1e20f}), side({0, 1, 3.5f}, {1e20f, 1, 3.5f});
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const Ray a = near.generate(float(x) + 0.5f, float(y) + 0.5f, 4, 4);
            const Ray b = far.generate(float(x) + 0.5f, float(y) + 0.5f, 4, 4);
            EXPECT_EQ(a.dir, b.dir) << x << "," << y;
            const Ray c = side.generate(float(x) + 0.5f, float(y) + 0.5f, 4, 4);
            EXPECT_TRUE(std::isfinite(c.dir.x) && std::isfinite(c.dir.y) && std::isfinite(c.dir.z));
            EXPECT_NEAR(length(c.dir), 1.0f, 1e-6f);
        }
    EXPECT_EQ(side.forward(), (Vec3{1, 0, 0}));
    EXPECT_EQ(Camera({0, 0, 0}, {0, 0, 1e-30f}).forward(), (Vec3{0, 0, 1}));  // tiny views too
    try {
        Camera({-3e38f, 0, 0}, {3e38f, 0, 0});
        ADD_FAILURE() << "a view direction of 6e38 was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("passes float's range"), std::string::npos) << e.what();
    }
}

TEST(Camera, AutoCameraSeesTheWholeBox) {
    const Aabb boxes[] = {
        {{-1.02f, 0, -1.04f}, {1, 1.99f, 0.99f}},            // Cornell box
        {{-17.4f, -0.9f, -7.8f}, {17.4f, 15.65f, 7.8f}},     // Sponza-like: wide
        {{-0.1f, 0.03f, -0.06f}, {0.06f, 0.19f, 0.06f}},     // bunny-like: small, off-centre
        {{100, 100, 100}, {100.5f, 130, 100.5f}},            // tall thin column far from the origin
        {{-5, 0, -5}, {5, 0, 5}},                             // flat floor
    };
    for (const Aabb& box : boxes) {
        for (const auto& [w, h] : {std::pair{640, 480}, {200, 400}, {900, 300}}) {
            const Camera cam = auto_camera(box, float(w) / float(h));
            EXPECT_GT(cam.position().z, box.max.z) << "camera on the +z side";
            EXPECT_GT(cam.position().y, box.center().y) << "camera slightly above";
            float lo_x = 1e9f, hi_x = -1e9f, lo_y = 1e9f, hi_y = -1e9f;
            for (int i = 0; i < 8; ++i) {
                const Vec3 c{(i & 1) ? box.max.x : box.min.x, (i & 2) ? box.max.y : box.min.y,
                             (i & 4) ? box.max.z : box.min.z};
                float px, py;
                ASSERT_TRUE(cam.project(c, w, h, px, py));
                EXPECT_GE(px, 0.0f);
                EXPECT_LE(px, float(w));
                EXPECT_GE(py, 0.0f);
                EXPECT_LE(py, float(h));
                lo_x = std::min(lo_x, px), hi_x = std::max(hi_x, px);
                lo_y = std::min(lo_y, py), hi_y = std::max(hi_y, py);
            }
            // Framed, not lost in the distance: the box spans most of the width or height.
            EXPECT_TRUE(hi_x - lo_x > 0.8f * float(w) || hi_y - lo_y > 0.8f * float(h))
                << "box spans " << hi_x - lo_x << " x " << hi_y - lo_y << " of " << w << "x" << h;
        }
    }
    const Camera empty = auto_camera(Aabb{}, 1.0f);  // empty scene: any valid camera
    EXPECT_NEAR(length(empty.forward()), 1.0f, 1e-6f);
}

TEST(Camera, ParseCameraString) {
    const Camera c = parse_camera("1,2,3, 0,0,0,30");
    expect_near_vec(c.position(), {1, 2, 3}, 0);
    expect_near_vec(c.target(), {0, 0, 0}, 0);
    EXPECT_EQ(c.fov_degrees(), 30.0f);
    EXPECT_EQ(parse_camera("0,0,1,0,0,-1e1").fov_degrees(), kDefaultFovDegrees);

    auto message = [](const char* text) -> std::string {
        try {
            parse_camera(text);
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_NE(message("1,2,3").find("expected 6 or 7"), std::string::npos);
    EXPECT_NE(message("1,2,3,4,5,6,7,8").find("got 8"), std::string::npos);
    EXPECT_NE(message("1,2,x,0,0,0").find("component 3 ('x')"), std::string::npos);
    EXPECT_NE(message("1,2,,0,0,0").find("component 3"), std::string::npos);
    EXPECT_NE(message("1,2,3,0,0,0,0").find("fov"), std::string::npos);
    EXPECT_NE(message("1,2,3,0,0,0,200").find("fov"), std::string::npos);
    EXPECT_NE(message("1,1,1,1,1,1").find("same point"), std::string::npos);
    EXPECT_NE(message("nan,0,0,0,0,0").find("not finite"), std::string::npos);
    // Issue 16: 1e39 was "not a number"; it is a number, beyond float's range.
    EXPECT_NE(message("1e39,0,0,0,0,0").find("component 1 ('1e39') is outside the range of float"), std::string::npos)
        << message("1e39,0,0,0,0,0");
    EXPECT_NE(message("0,-inf,0,0,0,0").find("component 2"), std::string::npos);
    EXPECT_NE(message("1,2,3,4,5").find("--camera '1,2,3,4,5'"), std::string::npos);
}

TEST(Image, PngRoundTripThroughStbImage) {
    Image img(37, 21);
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) img.at(x, y) = {uint8_t(x * 7), uint8_t(y * 12), uint8_t(x ^ y)};
    const fs::path dir = fs::temp_directory_path() / ("thicket_render_test_" + std::to_string(getpid()));
    fs::create_directories(dir);
    const std::string p = (dir / "img.png").string();
    write_png(img, p);
    int w = 0, h = 0;
    std::string why;
    const std::vector<unsigned char> data = thicket::testing::read_png_rgb(p, w, h, why);
    ASSERT_FALSE(data.empty()) << why;
    EXPECT_EQ(w, 37);
    EXPECT_EQ(h, 21);
    bool same = true;
    for (int i = 0; i < w * h * 3; ++i) same = same && data[i] == img.data()[i];
    EXPECT_TRUE(same);

    const std::string bad = (dir / "missing" / "img.png").string();
    try {
        write_png(img, bad);
        ADD_FAILURE() << "wrote into a missing directory";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "missing"));
    fs::remove_all(dir);
    EXPECT_THROW(Image(0, 10), Error);
}

TEST(Views, NormalViewFacesTheViewer) {
    const Scene scene = two_quads();
    const auto accel = build_accel("brute", scene);
    RenderOptions opt;
    opt.view = View::Normal;
    opt.width = 64;
    opt.height = 48;
    opt.progress = false;
    RenderStats stats;
    const Image front = render_view(scene, *accel, Camera({0, 0, 6}, {0, 0, 0}), opt, &stats);
    // Normal +z maps to (0.5, 0.5, 1) whichever side the camera sees.
    EXPECT_EQ(front.at(20, 24), (Rgb8{128, 128, 255}));
    EXPECT_EQ(front.at(44, 24), (Rgb8{128, 128, 255}));
    EXPECT_EQ(front.at(32, 1), (Rgb8{0, 0, 0})) << "misses are black";
    EXPECT_EQ(stats.rays, 64u * 48u);
    EXPECT_GT(stats.hits, 0u);
    EXPECT_LT(stats.hits, stats.rays);

    const Image back = render_view(scene, *accel, Camera({0, 0, -6}, {0, 0, 0}), opt);
    EXPECT_EQ(back.at(32 - 12, 24), (Rgb8{128, 128, 0})) << "back side: normal -z";
}

TEST(Views, DepthViewNormalisesBetweenNearestAndFarthestHit) {
    const Scene scene = two_quads();
    const auto accel = build_accel("brute", scene);
    RenderOptions opt;
    opt.view = View::Depth;
    opt.width = 80;
    opt.height = 60;
    opt.progress = false;
    opt.threads = 3;
    RenderStats stats;
    const Image img = render_view(scene, *accel, Camera({0, 0, 6}, {0, 0, 0}), opt, &stats);
    int brightest = 0, darkest_hit = 255;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x) {
            const Rgb8 c = img.at(x, y);
            ASSERT_TRUE(is_grey(c));
            brightest = std::max<int>(brightest, c.r);
            if (c.r > 0) darkest_hit = std::min<int>(darkest_hit, c.r);
        }
    EXPECT_EQ(brightest, 255);
    EXPECT_EQ(darkest_hit, 51);  // the farthest hit: 20% grey, never mistaken for a miss
    EXPECT_GT(img.at(25, 30).r, img.at(55, 30).r) << "the nearer quad is brighter";
    EXPECT_NEAR(stats.depth_near, 6.0, 1e-3);
    EXPECT_GT(stats.depth_far, 7.0);
}

TEST(Views, HeatmapScaleStatisticsAndLegend) {
    const Scene scene = two_quads();
    FakeAccel accel;
    RenderOptions opt;
    opt.view = View::Heatmap;
    opt.width = 320;
    opt.height = 240;
    opt.progress = false;
    RenderStats stats;
    const Image img = render_view(scene, accel, Camera({0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 90), opt, &stats);
    EXPECT_GT(stats.max_nodes, 70u);
    EXPECT_EQ(stats.heat_scale, double(stats.max_nodes));
    EXPECT_NEAR(stats.avg_nodes, 50.0, 1.0);
    EXPECT_EQ(stats.avg_prims, 2.0);
    EXPECT_GT(stats.rays_per_second, 0.0);
    ASSERT_TRUE(stats.legend_drawn);
    // Above the legend the image brightens from left to right with the work count.
    EXPECT_LT(luma(Vec3{float(img.at(10, 50).r), float(img.at(10, 50).g), float(img.at(10, 50).b)}),
              luma(Vec3{float(img.at(310, 50).r), float(img.at(310, 50).g), float(img.at(310, 50).b)}));

    // The legend band along the bottom: black background, a colour bar from black to white,
    // and white label pixels (the 5x7 font) below it.
    const int H = img.height(), W = img.width();
    EXPECT_EQ(img.at(0, H - 1), (Rgb8{0, 0, 0}));
    int bar_row = -1;  // the colour bar's lowest row, found from the bottom up
    for (int y = H - 1; y > H - 40 && bar_row < 0; --y)
        if (img.at(W - 4, y) == Rgb8{255, 255, 255} && img.at(W / 2, y) != Rgb8{0, 0, 0}) bar_row = y;
    ASSERT_GE(bar_row, 0) << "no colour bar ending in white near the bottom";
    int distinct = 0;
    Rgb8 prev{1, 2, 3};
    for (int x = 0; x < W; ++x)
        if (!(img.at(x, bar_row) == prev)) ++distinct, prev = img.at(x, bar_row);
    EXPECT_GT(distinct, 50) << "the bar should be a smooth ramp";
    int white_text = 0;
    for (int y = bar_row + 1; y < H; ++y)
        for (int x = 0; x < W; ++x) white_text += img.at(x, y) == Rgb8{255, 255, 255};
    EXPECT_GT(white_text, 20) << "tick labels missing";

    // A fixed scale saturates: everything above --heat-max is white.
    opt.heat_max = 10;
    opt.legend = false;
    const Image fixed = render_view(scene, accel, Camera({0, 0, 6}, {0, 0, 0}, {0, 1, 0}, 90), opt, &stats);
    EXPECT_EQ(stats.heat_scale, 10.0);
    EXPECT_FALSE(stats.legend_drawn);
    EXPECT_EQ(fixed.at(W - 1, H - 1), (Rgb8{255, 255, 255}));
}

TEST(Views, HeatRampGetsBrighterAndLegendSkipsTinyImages) {
    float prev = -1.0f;
    for (int i = 0; i <= 100; ++i) {
        const float l = luma(heat_colour(float(i) / 100.0f));
        EXPECT_GT(l, prev) << "at " << i;
        prev = l;
    }
    EXPECT_EQ(to_rgb8(heat_colour(0.0f)), (Rgb8{0, 0, 0}));
    EXPECT_EQ(to_rgb8(heat_colour(1.0f)), (Rgb8{255, 255, 255}));
    Image tiny(64, 40);
    EXPECT_FALSE(draw_heat_legend(tiny, 10));
    EXPECT_THROW(parse_view("phong"), Error);
    EXPECT_EQ(parse_view("heatmap"), View::Heatmap);
}

TEST(Font, DigitsAreDrawnAsGlyphs) {
    Image img(20, 9);
    draw_text(img, 1, 1, "17", 1, {255, 255, 255});
    // '1': a stem in column 2 of the glyph, a foot of three pixels on row 6.
    for (int row = 0; row < 7; ++row) EXPECT_EQ(img.at(1 + 2, 1 + row).r, 255) << row;
    EXPECT_EQ(img.at(1 + 1, 1 + 6).r, 255);
    EXPECT_EQ(img.at(1 + 0, 1 + 3).r, 0);
    // '7' starts one advance (6 px) later with a full top bar.
    for (int col = 0; col < 5; ++col) EXPECT_EQ(img.at(7 + col, 1).r, 255) << col;
    EXPECT_EQ(text_width("17", 2), 22);
}

TEST(Parallel, EveryIndexExactlyOnce) {
    for (unsigned threads : {0u, 1u, 2u, 7u})
        for (size_t grain : {size_t(1), size_t(3), size_t(1000)}) {
            std::vector<std::atomic<int>> seen(2501);
            parallel_for(seen.size(), grain, threads, [&](size_t b, size_t e) {
                EXPECT_LE(e - b, grain);
                for (size_t i = b; i < e; ++i) seen[i]++;
            });
            for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i].load(), 1) << i;
        }
    parallel_for(0, 1, 4, [](size_t, size_t) { FAIL() << "no work for an empty range"; });
}

/// Sets `*flag` when the thread that owns it ends: after parallel_for's worker has recorded its
/// exception and stopped the loop, since a worker's thread ends only when it leaves the loop.
struct SignalOnThreadExit {
    std::atomic<bool>* flag = nullptr;
    ~SignalOnThreadExit() {
        if (flag) flag->store(true, std::memory_order_release);
    }
};

TEST(Parallel, WorkerExceptionsReachTheCaller) {
    // Counted, not timed: the first chunk from index 17 on that a started thread takes throws;
    // every other chunk from 17 on waits until that thread has ended, so by then the failure is
    // recorded. Each of the other workers is then inside one waiting chunk at most and must start
    // no more: at most 17 chunks below 17, the thrower's, and one per other worker.
    constexpr size_t kChunks = 1000, kFirst = 17;
    for (unsigned threads : {1u, 2u, 4u}) {
        std::atomic<int> chunks{0};
        std::atomic<bool> thrower_chosen{false}, thrower_ended{false};
        const std::thread::id caller = std::this_thread::get_id();
        auto body = [&](size_t b, size_t) {
            ++chunks;
            if (b < kFirst) return;
            // One thread: the loop runs on the caller, which can just throw.
            if (threads == 1) throw std::runtime_error("chunk " + std::to_string(b));
            bool expected = false;
            if (std::this_thread::get_id() != caller && thrower_chosen.compare_exchange_strong(expected, true)) {
                thread_local SignalOnThreadExit signal;
                signal.flag = &thrower_ended;
                throw std::runtime_error("chunk " + std::to_string(b));
            }
            while (!thrower_ended.load(std::memory_order_acquire)) std::this_thread::yield();
        };
        EXPECT_THROW(parallel_for(kChunks, 1, threads, body), std::runtime_error) << threads << " threads";
        EXPECT_LE(chunks.load(), int(kFirst + threads)) << threads << " threads: work went on after a failure";
        if (threads == 1) {
            EXPECT_EQ(chunks.load(), int(kFirst + 1));
        }
    }
}

TEST(Progress, CountsAndFinishesQuietly) {
    Progress p("test", 100, "items", /*enabled=*/false);
    parallel_for(100, 7, 4, [&](size_t b, size_t e) { p.advance(e - b); });
    EXPECT_EQ(p.done(), 100u);
    p.finish();
    p.finish();
    p.abandon();
    EXPECT_EQ(format_si(1234567.0), "1.23 M");
    EXPECT_EQ(format_si(999.0), "999");
    EXPECT_EQ(format_duration(2.5), "2.5 s");
    EXPECT_EQ(format_duration(125.0), "2 min 05 s");
}

}  // namespace render_test
