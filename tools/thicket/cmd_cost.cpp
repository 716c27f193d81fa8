// `thicket cost`: the lecture's opening argument measured on its own example. A camera over the
// `spheres` scene shoots one ray per pixel and, from every hit, one shadow ray per light; brute
// force tests every sphere for each ray (pixels x (1 + lights) x spheres), a structure far fewer.
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "cost_command.h"
#include "thicket/bench/text_table.h"
#include "thicket/core/error.h"
#include "thicket/render/render_scene.h"
#include "thicket/util/input_file.h"
#include "thicket/util/parallel.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

namespace {

struct CostArgs {
    uint64_t pixels = 1000000;
    uint32_t spheres = 1000;
    uint32_t lights = 4;
    uint64_t seed = 1;
    std::vector<std::string> accels{"brute", "bvh8"};
    unsigned threads = 0;
    bool markdown = false;
};

std::string fixed(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

std::string sci(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

/// The primary rays of a side x side image and, for each hit, a shadow ray to every light's centre.
struct CostRays {
    std::vector<Ray> primary;
    std::vector<Ray> shadow;
};

CostRays make_rays(const SpheresScene& s, const Accel& reference, int side, uint32_t lights, unsigned threads) {
    CostRays rays;
    rays.primary.resize(size_t(side) * size_t(side));
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
            rays.primary[size_t(y) * size_t(side) + size_t(x)] =
                s.camera.generate(float(x) + 0.5f, float(y) + 0.5f, side, side);
    std::vector<Hit> hits(rays.primary.size());
    BatchOptions batch;
    batch.threads = threads;
    reference.intersect(rays.primary, hits, batch);
    // The lights are the last `lights` shapes of the scene.
    const size_t first_light = s.scene.shapes.size() - lights;
    for (size_t i = 0; i < hits.size(); ++i) {
        if (!hits[i].found()) continue;
        const Ray& r = rays.primary[i];
        const Vec3 p = r.org + r.dir * hits[i].t;
        const Vec3 n = s.scene.normal(r, hits[i]);
        for (uint32_t l = 0; l < lights; ++l) {
            const Sphere& light = std::get<Sphere>(s.scene.shapes[first_light + l]);
            const Vec3 d = light.center - p;
            const float dist = length(d);
            Ray sr;
            sr.dir = d / dist;
            sr.org = p + (dot(sr.dir, n) >= 0 ? n : -n) * (2e-4f * std::max(1.0f, max_component(abs(p))));
            sr.tmin = 0.0f;
            sr.tmax = std::max(0.0f, dist - light.radius * 1.001f);
            rays.shadow.push_back(sr);
        }
    }
    return rays;
}

int run_cost(const CostArgs& args) {
    if (args.pixels < 1 || args.pixels > 100000000ull) throw Error("--pixels must be between 1 and 100000000");
    const int side = int(std::lround(std::sqrt(double(args.pixels))));
    if (side < 1) throw Error("--pixels must be at least 1");
    const std::vector<AskedSpec> specs = parse_accel_specs(args.accels);
    const uint64_t pixels = uint64_t(side) * uint64_t(side);
    // The camera rays and their hits, then up to one shadow ray and flag per light and pixel:
    // checked before the scene is made, so that no count reaches std::bad_alloc.
    if (args.lights <= 64)
        check_memory(pixels * (sizeof(Ray) + sizeof(Hit)) + pixels * args.lights * (sizeof(Ray) + 1),
                     "--pixels " + std::to_string(args.pixels) + " with --lights " + std::to_string(args.lights) +
                         ": the camera and shadow rays");
    const SpheresScene s = make_spheres_scene(args.spheres, args.lights, args.seed);
    const double spheres_total = double(s.scene.shapes.size());  // the lights are spheres too
    const double analytic = double(pixels) * (1.0 + args.lights) * spheres_total;
    std::printf("scene   spheres: %u spheres, %u light spheres and a ground of 2 triangles (%zu spheres in all), seed %llu\n",
                args.spheres, args.lights, s.scene.shapes.size(), static_cast<unsigned long long>(args.seed));
    std::printf("image   %dx%d = %llu pixels, 1 camera ray per pixel and 1 shadow ray per light from each hit\n",
                side, side, static_cast<unsigned long long>(pixels));
    std::printf("analytic brute force: pixels x (1 + lights) x spheres = %llu x %u x %.0f = %s intersection tests\n",
                static_cast<unsigned long long>(pixels), 1 + args.lights, spheres_total, sci(analytic).c_str());
    std::fflush(stdout);

    const std::unique_ptr<Accel> reference = build_accel("bvh", s.scene, args.threads);
    const CostRays rays = make_rays(s, *reference, side, args.lights, args.threads);
    const double ray_count = double(rays.primary.size() + rays.shadow.size());
    std::printf("rays    %zu camera + %zu shadow = %.0f\n", rays.primary.size(), rays.shadow.size(), ray_count);

    TextTable table({"structure", "tests counted", "tests/ray", "reduction vs analytic", "build", "trace wall",
                     "ns/ray", "ns/test"},
                    {TextTable::Align::Left, TextTable::Align::Right, TextTable::Align::Right, TextTable::Align::Right,
                     TextTable::Align::Right, TextTable::Align::Right, TextTable::Align::Right,
                     TextTable::Align::Right});
    for (const AskedSpec& asked : specs) {
        const std::string& spec = asked.text;
        const std::unique_ptr<Accel> accel = build_accel(asked.spec, s.scene, args.threads);
        // Counted pass: every ray with RayCounters (closest hit for camera rays, any hit for shadow rays).
        std::atomic<uint64_t> tests{0};
        Progress progress("count " + spec, uint64_t(ray_count), "rays");
        parallel_for(rays.primary.size() + rays.shadow.size(), 1024, args.threads, [&](size_t b, size_t e) {
            RayCounters c;
            for (size_t i = b; i < e; ++i) {
                if (i < rays.primary.size())
                    accel->intersect(rays.primary[i], c);
                else
                    accel->occluded(rays.shadow[i - rays.primary.size()], c);
            }
            tests += c.prims;
            progress.advance(e - b);
        });
        progress.finish();
        // Timed pass: the batch API without counters.
        std::vector<Hit> hits(rays.primary.size());
        std::vector<uint8_t> blocked(rays.shadow.size());
        BatchOptions batch;
        batch.threads = args.threads;
        const auto start = std::chrono::steady_clock::now();
        accel->intersect(rays.primary, hits, batch);
        accel->occluded(rays.shadow, blocked, batch);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double t = double(tests.load());
        table.add_row({spec, sci(t), fixed(t / ray_count, 1), t > 0 ? fixed(analytic / t, 1) + "x" : "-",
                       format_duration(accel->build_ms() / 1000), format_duration(seconds),
                       fixed(seconds * 1e9 / ray_count, 1), t > 0 ? fixed(seconds * 1e9 / t, 2) : "-"});
    }
    std::printf("\n%s", args.markdown ? table.markdown().c_str() : table.terminal().c_str());
    std::printf("\n(trace wall: both batches on %u threads, load average %s; tests: primitive intersection tests "
                "counted with RayCounters)\n",
                resolve_threads(args.threads), load_average().c_str());
    return 0;
}

}  // namespace

Command add_cost_command(CLI::App& app) {
    auto args = std::make_shared<CostArgs>();
    CLI::App* cmd = app.add_subcommand("cost", "count the intersection tests of the lecture's example: brute force "
                                               "against the structures");
    cmd->footer("The scene is the built-in `spheres` scene. The analytic estimate is pixels x (1 + lights) x "
                "spheres (every ray tests every sphere); the counted figures come from the structures' RayCounters "
                "(shadow rays stop at their first hit, and rays that miss cast no shadow rays, so brute force "
                "counts fewer than the estimate).");
    cmd->add_option("--pixels", args->pixels, "camera rays (a square image of about this many pixels, 1 to 100000000)")
        ->check(whole_number(0, UINT64_MAX))
        ->default_str("1000000")
        ->type_name("N");
    cmd->add_option("--spheres", args->spheres, "spheres in the scene (besides the ground and the lights; checked "
                                                "against the memory available)")
        ->check(whole_number(0, UINT32_MAX))
        ->default_str("1000")
        ->type_name("N");
    cmd->add_option("--lights", args->lights, "lights (small spheres, at most 64), one shadow ray each per hit")
        ->check(whole_number(0, UINT32_MAX))
        ->default_str("4")
        ->type_name("N");
    cmd->add_option("--seed", args->seed, "scene seed (placement and colours), 0 to 2^64 - 1")
        ->check(whole_number(0, UINT64_MAX))
        ->default_str("1")
        ->type_name("S");
    cmd->add_option("-a,--accel", args->accels, "structures to measure (repeatable; `all`: every registered variant)")
        ->default_str("brute bvh8")
        ->type_name("SPEC");
    cmd->add_flag("--markdown", args->markdown, "print the table as Markdown (for BENCHMARKS.md)");
    add_threads_option(cmd, args->threads);
    return {cmd, [args] { return run_cost(*args); }};
}

}  // namespace thicket::cli
