// `thicket render --integrator path|whitted`.
#include "render_path.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "thicket/core/error.h"
#include "thicket/render/film.h"
#include "thicket/render/integrator.h"
#include "thicket/render/lights.h"
#include "thicket/render/render_json.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

void add_light_render_options(CLI::App* cmd, LightRenderArgs& args) {
    cmd->add_option("-i,--integrator", args.integrator,
                    "render with light instead of a preview view: path (path tracing: next event estimation "
                    "and BSDF sampling combined by MIS, Russian roulette) or whitted (mirror and glass "
                    "recursion, hard shadows). SCENE may also be `spheres` (the lecture's 1,000 spheres and 4 lights). "
                    "-o x.png writes sRGB (tone-mapped), -o x.exr linear float RGB")
        ->type_name("NAME");
    cmd->add_option("--spp", args.spp, "with --integrator: samples per pixel (with --time: per pass)")
        ->default_str("16")
        ->type_name("N");
    cmd->add_option("--seed", args.seed, "with --integrator: random seed; the image is bit-identical for a seed "
                                         "whatever --threads is (unless --time)")
        ->default_str("0")
        ->type_name("S");
    cmd->add_option("--time", args.time, "with --integrator: render passes of --spp samples until SECONDS have "
                                         "passed (at least one pass)")
        ->type_name("SECONDS");
    cmd->add_option("--exposure", args.exposure, "with --integrator: radiance scale (before sRGB tone mapping for PNG; EXR gets "
                                                 "the scaled linear values)")
        ->default_str("1")
        ->type_name("X");
    cmd->add_option("--max-depth", args.max_depth, "with --integrator: path segments at most")
        ->default_str("64")
        ->type_name("N");
    cmd->add_option("--spheres", args.spheres, "scene `spheres`: number of spheres")
        ->default_str("1000")
        ->type_name("N");
    cmd->add_option("--lights", args.lights, "scene `spheres`: number of small spherical area lights")
        ->default_str("4")
        ->type_name("N");
    cmd->add_option("--scene-seed", args.scene_seed, "scene `spheres`: seed of the placement and colours")
        ->default_str("1")
        ->type_name("S");
}

namespace {

bool ends_with(const std::string& s, const char* suffix) {
    const std::string t(suffix);
    return s.size() >= t.size() && s.compare(s.size() - t.size(), t.size(), t) == 0;
}

}  // namespace

int run_light_render(const std::string& scene_name, const AccelChoice& accel_choice, int width, int height,
                     const std::string& camera_text, const std::string& output, unsigned threads,
                     const LightRenderArgs& args) {
    // Every option is checked before the slow work.
    const Integrator integrator = parse_integrator(args.integrator);
    if (args.spp < 1) throw Error("--spp must be at least 1");
    if (!(args.time >= 0.0) || !std::isfinite(args.time)) throw Error("--time must be a number of seconds >= 0");
    if (!(args.exposure > 0.0f) || !std::isfinite(args.exposure)) throw Error("--exposure must be a number > 0");
    if (args.max_depth < 1) throw Error("--max-depth must be at least 1");
    const bool exr = ends_with(output, ".exr") || ends_with(output, ".EXR");
    std::optional<Camera> camera;
    if (!camera_text.empty()) camera = parse_camera(camera_text);
    const std::optional<AccelSpec> spec = validate_accel_choice(accel_choice);

    std::optional<SpheresScene> spheres;
    Scene loaded;
    const Scene* scene = nullptr;
    RenderScene rs;
    if (scene_name == "spheres") {
        spheres = make_spheres_scene(args.spheres, args.lights, args.scene_seed);
        scene = &spheres->scene;
        rs = render_scene_of(*spheres);
        std::printf("scene   spheres: %u spheres on a ground square, %u lights, scene seed %llu\n", args.spheres,
                    args.lights, static_cast<unsigned long long>(args.scene_seed));
    } else {
        loaded = load_scene_verbose(scene_name);
        scene = &loaded;
        rs = make_render_scene(loaded);
        if (ends_with(scene_name, ".json") || ends_with(scene_name, ".JSON"))
            apply_json_render_settings(scene_name, rs);  // its materials, lights and camera
    }
    const std::unique_ptr<Accel> accel = make_accel_verbose(accel_choice, spec, *scene, threads);
    if (!camera) camera = rs.camera ? *rs.camera : auto_camera(scene->bounds(), float(width) / float(height));
    // Nothing emits: a point light at the camera sized by what the camera sees (said on stderr).
    add_automatic_light(rs, *accel, *camera, width, height);
    std::fflush(stdout);

    TraceOptions options;
    options.width = width;
    options.height = height;
    options.spp = args.spp;
    options.seed = args.seed;
    options.threads = threads;
    options.max_depth = args.max_depth;
    const auto start = std::chrono::steady_clock::now();
    TraceResult result = trace_image(rs, *accel, *camera, integrator, options);
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    while (args.time > 0.0 && elapsed() < args.time) {
        options.first_sample = result.spp;  // the next pass continues the sample sequence
        accumulate(result, trace_image(rs, *accel, *camera, integrator, options));
    }
    std::printf("render  %dx%d %s, %u spp (seed %llu): %s rays in %s, %s rays/s, %s samples/s\n", width, height,
                integrator_name(integrator), result.spp, static_cast<unsigned long long>(args.seed),
                format_si(double(result.rays)).c_str(), format_duration(result.seconds).c_str(),
                format_si(result.seconds > 0 ? double(result.rays) / result.seconds : 0.0).c_str(),
                format_si(result.seconds > 0 ? double(width) * height * result.spp / result.seconds : 0.0).c_str());

    const std::filesystem::path out(output);
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
    if (exr)
        write_exr(result.radiance, width, height, output, args.exposure);  // linear: no tone mapping
    else
        write_png(tonemap_srgb(result.radiance, width, height, args.exposure), output);
    std::printf("wrote   %s\n", output.c_str());
    return 0;
}

}  // namespace thicket::cli
