#include "thicket/render/views.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/util/input_file.h"
#include "thicket/util/parallel.h"
#include "thicket/util/progress.h"
#include "trace_common.h"

namespace thicket {

namespace {

constexpr Rgb8 kBlack{0, 0, 0};
constexpr Rgb8 kWhite{255, 255, 255};

// Farthest hits stay visibly grey so they never read as misses (black).
constexpr float kDepthFarGrey = 0.2f;

std::string format_tick(double v) {
    char buf[32];
    if (v == std::floor(v) && std::fabs(v) < 1e9)
        std::snprintf(buf, sizeof buf, "%.0f", v);
    else
        std::snprintf(buf, sizeof buf, "%.1f", v);
    return buf;
}

Vec3 normal_colour(const Scene& scene, const Hit& hit, const Ray& ray) {
    Vec3 n = scene.normal(ray, hit);
    if (n == Vec3{}) return Vec3{0.5f};  // zero-area triangle: no direction
    if (dot(n, ray.dir) > 0.0f) n = -n;  // show the side the viewer sees
    return n * 0.5f + Vec3{0.5f};
}

}  // namespace

View parse_view(std::string_view name) {
    if (name == "depth") return View::Depth;
    if (name == "normal") return View::Normal;
    if (name == "heatmap") return View::Heatmap;
    throw Error("unknown view '" + std::string(name) + "' (choose depth, normal or heatmap)");
}

const char* view_name(View view) {
    switch (view) {
        case View::Depth: return "depth";
        case View::Normal: return "normal";
        case View::Heatmap: return "heatmap";
    }
    return "?";
}

Vec3 heat_colour(float x) {
    struct Stop {
        float at;
        Vec3 c;
    };
    static constexpr Stop kStops[] = {
        {0.00f, {0.00f, 0.00f, 0.00f}},  // black
        {0.18f, {0.12f, 0.07f, 0.60f}},  // blue
        {0.40f, {0.70f, 0.12f, 0.65f}},  // magenta
        {0.62f, {1.00f, 0.45f, 0.15f}},  // orange
        {0.82f, {1.00f, 0.85f, 0.15f}},  // yellow
        {1.00f, {1.00f, 1.00f, 1.00f}},  // white
    };
    if (!(x > 0.0f)) return kStops[0].c;
    if (x >= 1.0f) return kStops[5].c;
    int i = 0;
    while (x > kStops[i + 1].at) ++i;
    const float f = (x - kStops[i].at) / (kStops[i + 1].at - kStops[i].at);
    return kStops[i].c + (kStops[i + 1].c - kStops[i].c) * f;
}

bool draw_heat_legend(Image& image, double max_value, std::string_view title) {
    const int W = image.width(), H = image.height();
    // One font pixel per 240 image rows keeps the labels about 3% of the height.
    const int s = std::max(1, std::min(W / 320, H / 240));
    const int margin = 3 * s, bar_h = 8 * s, band_h = 2 * s + bar_h + 3 * s + text_height(s) + 2 * s;
    std::string label(title);
    if (W < 160 * s) label = "nodes";  // narrow images: keep room for the bar
    const int bx0 = margin + text_width(label, s) + 4 * s, bx1 = W - margin;
    if (bx1 - bx0 < 40 * s || H < 2 * band_h) return false;

    const int y0 = H - band_h, bar_y = y0 + 2 * s;
    image.fill_rect(0, y0, W, H, kBlack);
    draw_text(image, margin, bar_y + (bar_h - text_height(s)) / 2, label, s, kWhite);
    for (int x = bx0; x < bx1; ++x) {
        const Rgb8 c = to_rgb8(heat_colour(float(x - bx0) / float(bx1 - bx0 - 1)));
        image.fill_rect(x, bar_y, x + 1, bar_y + bar_h, c);
    }
    // Ticks under 0, max/2 and max, with labels left-aligned, centred and right-aligned on them.
    const int ticks[3] = {bx0, bx0 + (bx1 - bx0) / 2, bx1 - s};
    const std::string labels[3] = {"0", format_tick(max_value / 2), format_tick(max_value)};
    const int label_y = bar_y + bar_h + 3 * s;
    for (int i = 0; i < 3; ++i) {
        image.fill_rect(ticks[i], bar_y + bar_h, ticks[i] + s, bar_y + bar_h + 2 * s, kWhite);
        const int w = text_width(labels[i], s);
        const int lx = i == 0 ? ticks[0] : (i == 1 ? ticks[1] - w / 2 : bx1 - w);
        draw_text(image, lx, label_y, labels[i], s, kWhite);
    }
    return true;
}

Image render_view(const Scene& scene, const Accel& accel, const Camera& camera, const RenderOptions& options,
                  RenderStats* stats_out) {
    const int W = options.width, H = options.height;
    Image image(W, H);  // validates the size
    if (!(options.heat_max >= 0.0) || !std::isfinite(options.heat_max))
        throw Error("heat-max must be a non-negative number");

    const size_t pixels = size_t(W) * size_t(H);
    // Per-pixel results kept until the image-wide normalisation (depth range, heat scale) is known.
    std::vector<float> depth(options.view == View::Depth ? pixels : 0, -1.0f);
    std::vector<uint32_t> nodes(options.view == View::Heatmap ? pixels : 0, 0);
    std::atomic<uint64_t> hits{0}, prims_tested{0}, nodes_visited{0};

    Progress progress("render", uint64_t(pixels), "rays", options.progress);
    const auto start = std::chrono::steady_clock::now();
    // Tiles are the unit of work, their pixels in 4x4 blocks (Tiling), so that each 16
    // consecutive rays are neighbours: the batch API's packets (bvh8) trace them together.
    const Tiling tiling{W, H};
    parallel_for(tiling.count(), 1, options.threads, [&](size_t tile_begin, size_t tile_end) {
        uint64_t chunk_hits = 0, chunk_prims = 0, chunk_nodes = 0, chunk_rays = 0;
        std::vector<Ray> rays;
        std::vector<uint32_t> pixel;  // image index of each ray
        std::vector<Hit> found;
        for (size_t tile = tile_begin; tile < tile_end; ++tile) {
            tile_camera_rays(camera, tiling, tile, pixel, rays);
            trace_tile(accel, rays, found, options.view == View::Heatmap, [&](size_t k, const RayCounters& counters) {
                nodes[pixel[k]] = uint32_t(std::min<uint64_t>(counters.nodes, std::numeric_limits<uint32_t>::max()));
                chunk_nodes += counters.nodes;
                chunk_prims += counters.prims;
            });
            for (size_t k = 0; k < rays.size(); ++k) {
                const Hit& hit = found[k];
                if (!hit.found()) continue;
                ++chunk_hits;
                if (options.view == View::Depth)
                    depth[pixel[k]] = hit.t;
                else if (options.view == View::Normal)
                    image.at(int(pixel[k] % uint32_t(W)), int(pixel[k] / uint32_t(W))) =
                        to_rgb8(normal_colour(scene, hit, rays[k]));
            }
            chunk_rays += rays.size();
        }
        hits += chunk_hits;
        prims_tested += chunk_prims;
        nodes_visited += chunk_nodes;
        progress.advance(chunk_rays);
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    progress.finish();

    RenderStats stats;
    stats.rays = pixels;
    stats.hits = hits;
    stats.seconds = seconds;
    stats.rays_per_second = seconds > 0 ? double(pixels) / seconds : 0.0;

    if (options.view == View::Depth) {
        float near = kInfinity, far = -kInfinity;
        for (float t : depth) {
            if (!(t >= 0.0f) || !std::isfinite(t)) continue;
            near = std::min(near, t);
            far = std::max(far, t);
        }
        if (near <= far) {
            stats.depth_near = near;
            stats.depth_far = far;
        }
        const float range = far - near;
        for (size_t i = 0; i < pixels; ++i) {
            const float t = depth[i];
            if (!(t >= 0.0f) || !std::isfinite(t)) continue;
            const float f = range > 0.0f ? (t - near) / range : 0.0f;
            const Rgb8 grey = to_rgb8(Vec3{1.0f - (1.0f - kDepthFarGrey) * f});
            image.at(int(i % size_t(W)), int(i / size_t(W))) = grey;
        }
    } else if (options.view == View::Heatmap) {
        const uint32_t max_nodes = nodes.empty() ? 0 : *std::max_element(nodes.begin(), nodes.end());
        stats.max_nodes = max_nodes;
        stats.avg_nodes = double(nodes_visited.load()) / double(pixels);
        stats.avg_prims = double(prims_tested.load()) / double(pixels);
        stats.heat_scale = options.heat_max > 0.0 ? options.heat_max : std::max<double>(max_nodes, 1.0);
        for (size_t i = 0; i < pixels; ++i)
            image.at(int(i % size_t(W)), int(i / size_t(W))) =
                to_rgb8(heat_colour(float(double(nodes[i]) / stats.heat_scale)));
        if (options.legend) stats.legend_drawn = draw_heat_legend(image, stats.heat_scale);
    }
    if (stats_out) *stats_out = stats;
    return image;
}

void parse_image_size(std::string_view text_view, int& width, int& height) {
    const std::string text(text_view);
    const size_t x = text.find_first_of("xX");
    auto number = [&](std::string_view s, int& out) {
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
        return !s.empty() && ec == std::errc() && end == s.data() + s.size();
    };
    if (x == std::string::npos || !number(std::string_view(text).substr(0, x), width) ||
        !number(std::string_view(text).substr(x + 1), height))
        throw Error("--size '" + text + "': expected WIDTHxHEIGHT, e.g. 640x480");
    if (width < 1 || height < 1 || width > Image::kMaxSide || height > Image::kMaxSide)
        throw Error("--size '" + text + "': width and height must be between 1 and " + std::to_string(Image::kMaxSide));
    // The RGB image, the depth or node-count buffer, and the PNG encoding of it: checked before the
    // scene is loaded, so a size that cannot fit fails at once and says how much it needs.
    const uint64_t pixels = uint64_t(width) * uint64_t(height);
    check_memory(pixels * (3 + 4 + 4), "--size " + text + ": the image (" + std::to_string(pixels) + " pixels)");
}


}  // namespace thicket
