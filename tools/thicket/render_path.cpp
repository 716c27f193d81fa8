// `thicket render --integrator path|whitted`.
#include "render_path.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>

#include "thicket/core/error.h"
#include "thicket/render/film.h"
#include "thicket/render/integrator.h"
#include "thicket/render/lights.h"
#include "thicket/render/render_json.h"
#include "thicket/util/atomic_file.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

void add_light_render_options(CLI::App* cmd, LightRenderArgs& args) {
    constexpr uint64_t kU32 = UINT32_MAX, kU64 = UINT64_MAX;
    cmd->add_option("-i,--integrator", args.integrator,
                    "render with light instead of a preview view: path (path tracing: next event estimation "
                    "and BSDF sampling combined by MIS, Russian roulette) or whitted (mirror and glass "
                    "recursion, hard shadows). SCENE may also be `spheres` (the lecture's 1,000 spheres and 4 lights; "
                    "the preview views take it too). "
                    "-o x.png writes sRGB (tone-mapped), -o x.exr linear float RGB")
        ->type_name("NAME");
    cmd->add_option("--spp", args.spp, "with --integrator only: samples per pixel (with --time: per pass)")
        ->check(whole_number(0, kU32))
        ->default_str("16")
        ->type_name("N");
    cmd->add_option("--seed", args.seed, "with --integrator only: random seed, 0 to 2^64 - 1; the image is "
                                         "bit-identical for a seed whatever --threads is (unless --time)")
        ->check(whole_number(0, kU64))
        ->default_str("0")
        ->type_name("S");
    cmd->add_option("--time", args.time, "with --integrator only: render passes of --spp samples until SECONDS have "
                                         "passed (at least one pass)")
        ->type_name("SECONDS");
    cmd->add_option("--exposure", args.exposure, "with --integrator only: radiance scale, > 0 and within float's range "
                                                 "(1.2e-38 to 3.4e38), applied before sRGB tone mapping for PNG; EXR "
                                                 "gets the scaled linear values")
        ->default_str("1")
        ->type_name("X");
    cmd->add_option("--max-depth", args.max_depth, "with --integrator only: path segments at most")
        ->check(whole_number(0, kU32))
        ->default_str("64")
        ->type_name("N");
    cmd->add_option("--spheres", args.spheres, "scene `spheres` only: number of spheres")
        ->check(whole_number(0, kU32))
        ->default_str("1000")
        ->type_name("N");
    cmd->add_option("--lights", args.lights, "scene `spheres` only: number of small spherical area lights (at most 64)")
        ->check(whole_number(0, kU32))
        ->default_str("4")
        ->type_name("N");
    cmd->add_option("--scene-seed", args.scene_seed, "scene `spheres` only: seed of the placement and colours")
        ->check(whole_number(0, kU64))
        ->default_str("1")
        ->type_name("S");
}

void refuse_light_options_that_do_not_apply(const CLI::App* cmd, const std::string& scene_name,
                                            const LightRenderArgs& args) {
    const CLI::Option* integrator = cmd->get_option("--integrator");
    if (integrator->count() > 0 && args.integrator.empty())
        throw Error("--integrator '' is empty: name path or whitted (or leave --integrator out for a preview --view)");
    if (args.integrator.empty())
        for (const char* o : {"--spp", "--seed", "--time", "--exposure", "--max-depth"})
            refuse_if_given(cmd, o, "it sets the light transport of --integrator path|whitted; the preview "
                                    "views (--view) take one ray per pixel and no samples");
    if (scene_name != "spheres")
        for (const char* o : {"--spheres", "--lights", "--scene-seed"})
            refuse_if_given(cmd, o, "it shapes the generated scene `spheres`, and the scene is " + scene_name);
}

ImageFormat output_image_format(const std::string& output) {
    if (output == "-") return ImageFormat::Png;
    const std::filesystem::path path(output);
    if (path.extension().empty() && resolve_output(output).kind == OutputTarget::Special) return ImageFormat::Png;
    return image_format_of(output);
}

namespace {

bool ends_with(const std::string& s, const char* suffix) {
    const std::string t(suffix);
    return s.size() >= t.size() && s.compare(s.size() - t.size(), t.size(), t) == 0;
}

/// --exposure as a float: > 0 and within float's normal range, the message saying which bound a
/// value breaks (1e39 overflows float, 1e-50 rounds to 0), not merely "must be a number".
float checked_exposure(double exposure) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", exposure);
    if (std::isnan(exposure)) throw Error("--exposure nan is not a number");
    if (!(exposure > 0.0)) throw Error(std::string("--exposure ") + text + " must be > 0 (it scales the radiance)");
    if (exposure > double(std::numeric_limits<float>::max()))
        throw Error(std::string("--exposure ") + text + " is beyond float's range (at most 3.4e38)");
    if (exposure < double(std::numeric_limits<float>::min()))
        throw Error(std::string("--exposure ") + text + " is below float's smallest normal value (1.2e-38): it would "
                    "round to 0 or lose its precision");
    return float(exposure);
}

}  // namespace

int run_light_render(const std::string& scene_name, const AccelChoice& accel_choice, int width, int height,
                     const std::string& camera_text, const std::string& output, unsigned threads,
                     const LightRenderArgs& args) {
    // Every option is checked before the slow work.
    const Integrator integrator = parse_integrator(args.integrator);
    if (args.spp < 1) throw Error("--spp must be at least 1");
    if (std::isnan(args.time)) throw Error("--time nan is not a number of seconds");
    if (!(args.time >= 0.0)) throw Error("--time " + std::to_string(args.time) + " is negative: give seconds >= 0");
    if (!std::isfinite(args.time)) throw Error("--time is infinite (beyond double's range): give a finite number of seconds");
    const float exposure = checked_exposure(args.exposure);
    if (args.max_depth < 1) throw Error("--max-depth must be at least 1");
    const bool exr = output_image_format(output) == ImageFormat::Exr;
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
        write_exr(result.radiance, width, height, output, exposure);  // linear: no tone mapping
    else
        write_png(tonemap_srgb(result.radiance, width, height, exposure), output);
    std::printf("wrote   %s\n", output.c_str());
    return 0;
}

}  // namespace thicket::cli
