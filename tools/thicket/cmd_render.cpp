// `thicket render`: a preview image through a structure (depth, normal or heatmap view).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "common.h"
#include "render_path.h"
#include "thicket/core/error.h"
#include "thicket/render/render_scene.h"
#include "thicket/render/views.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

namespace {

struct RenderArgs {
    std::string scene;
    AccelChoice accel;
    std::string view = "normal";
    std::string size = "640x480";
    std::string camera;
    double heat_max = 0.0;
    bool no_legend = false;
    std::string output = "render.png";
    bool force = false;
    unsigned threads = 0;
    LightRenderArgs light;  // --integrator and its options (render_path.cpp)
};

std::string vec_text(Vec3 v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%g,%g,%g", double(v.x), double(v.y), double(v.z));
    return buf;
}

int run_render(const CLI::App* cmd, const RenderArgs& args) {
    // Check every option before the slow work, so a typo costs nothing; an option that does not
    // apply is refused rather than ignored.
    RenderOptions options;
    options.view = parse_view(args.view);
    parse_image_size(args.size, options.width, options.height);
    refuse_light_options_that_do_not_apply(cmd, args.scene, args.light);
    refuse_output_is_input(args.output, {args.scene, args.accel.load});  // the worse mistake, named first
    const ImageFormat format = output_image_format(args.output);
    if (!args.light.integrator.empty()) {
        for (const char* o : {"--view", "--heat-max", "--no-legend"})
            refuse_if_given(cmd, o, "it belongs to the preview views; --integrator " + args.light.integrator +
                                    " renders with light");
        const std::string output = prepare_output(args.output, args.force, {args.scene, args.accel.load});
        return run_light_render(args.scene, args.accel, options.width, options.height, args.camera, output,
                                args.threads, args.light);
    }
    options.threads = args.threads;
    options.heat_max = args.heat_max;
    options.legend = !args.no_legend;
    if (!(args.heat_max >= 0.0) || !std::isfinite(args.heat_max))
        throw Error("--heat-max " + std::to_string(args.heat_max) +
                    " is not a finite node count >= 0 (0: the image's maximum)");
    if (options.view != View::Heatmap)
        for (const char* o : {"--heat-max", "--no-legend"})
            refuse_if_given(cmd, o, "it sets the heatmap's colour scale; the view is " + args.view);
    if (format == ImageFormat::Exr)
        throw Error(args.output + ": the preview views are 8-bit pictures, written as .png; .exr (linear float) is "
                    "for --integrator path|whitted");
    std::optional<Camera> camera;
    if (!args.camera.empty()) camera = parse_camera(args.camera);
    const std::optional<AccelSpec> spec = validate_accel_choice(args.accel);
    const std::string output = prepare_output(args.output, args.force, {args.scene, args.accel.load});

    // `spheres`: the generated scene of --integrator, seen by the preview from its own camera.
    std::optional<SpheresScene> spheres;
    Scene loaded;
    if (args.scene == "spheres" && !std::filesystem::exists(args.scene)) {
        spheres = make_spheres_scene(args.light.spheres, args.light.lights, args.light.scene_seed);
        std::printf("scene   spheres: %u spheres on a ground square, %u lights, scene seed %llu\n", args.light.spheres,
                    args.light.lights, static_cast<unsigned long long>(args.light.scene_seed));
        if (!camera) camera = spheres->camera;
    } else {
        loaded = load_scene_verbose(args.scene);
    }
    const Scene& scene = spheres ? spheres->scene : loaded;
    const std::unique_ptr<Accel> accel = make_accel_verbose(args.accel, spec, scene, args.threads);
    if (!camera) camera = auto_camera(scene.bounds(), float(options.width) / float(options.height));
    // Rays from or toward coordinates past 1e18 overflow float in the triangle test: the image
    // comes out empty. Say why rather than leave a black picture unexplained.
    {
        const Vec3 p = camera->position();
        const float far = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
        if (!(far <= kLargeCoordinate))
            std::fprintf(stderr, "warning: the camera stands at %g from the origin (the scene's bounds reach that far): "
                                 "float arithmetic overflows beyond 1e18 and the image may be empty\n", double(far));
    }
    std::printf("camera  --camera %s,%s,%g%s\n", vec_text(camera->position()).c_str(),
                vec_text(camera->target()).c_str(), double(camera->fov_degrees()), args.camera.empty() ? " (auto)" : "");
    std::fflush(stdout);

    RenderStats stats;
    const Image image = render_view(scene, *accel, *camera, options, &stats);
    std::printf("render  %dx%d %s view: %s rays in %s, %s rays/s, %.1f%% hit\n", options.width, options.height,
                view_name(options.view), format_si(double(stats.rays)).c_str(),
                format_duration(stats.seconds).c_str(), format_si(stats.rays_per_second).c_str(),
                stats.rays ? 100.0 * double(stats.hits) / double(stats.rays) : 0.0);
    if (options.view == View::Depth && stats.hits)
        std::printf("depth   white at t = %g, dark grey at t = %g\n", stats.depth_near, stats.depth_far);
    if (options.view == View::Heatmap) {
        std::printf("heatmap scale 0..%g nodes (%s); nodes visited per ray: %.2f average, %llu max; "
                    "primitives tested per ray: %.2f average%s\n",
                    stats.heat_scale, args.heat_max > 0 ? "--heat-max" : "image maximum", stats.avg_nodes,
                    static_cast<unsigned long long>(stats.max_nodes), stats.avg_prims,
                    stats.legend_drawn || !options.legend ? "" : " (image too small for the legend)");
    }

    const std::filesystem::path out(output);
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
    write_png(image, output);
    std::printf("wrote   %s\n", args.output.c_str());
    return 0;
}

}  // namespace

Command add_render_command(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    CLI::App* cmd = app.add_subcommand("render", "render a preview image of SCENE through a structure");
    cmd->footer("Views: depth (grey by hit distance, nearest white; misses black), normal (geometric normal "
                "of the hit triangle faced toward the viewer, as RGB = 0.5 n + 0.5), heatmap (nodes visited "
                "per ray, with a colour-bar legend). Without --camera the camera looks at the scene's bounding "
                "box from the +z side, 10 degrees above it, framing all eight corners.");
    add_scene_argument(cmd, args->scene);
    add_accel_options(cmd, args->accel);
    cmd->add_option("-v,--view", args->view, "what to show: depth, normal or heatmap")->default_str("normal");
    cmd->add_option("-s,--size", args->size, "image size WIDTHxHEIGHT")->default_str("640x480")->type_name("WxH");
    cmd->add_option("-c,--camera", args->camera,
                    "camera position and target (and vertical field of view in degrees, default 45); up is +y")
        ->type_name("px,py,pz,tx,ty,tz[,fov]");
    cmd->add_option("--heat-max", args->heat_max,
                    "heatmap: node count at the top of the colour ramp (default: the image's maximum), "
                    "so that images of different structures share one scale")
        ->type_name("N");
    cmd->add_flag("--no-legend", args->no_legend, "heatmap: leave out the colour-bar legend");
    cmd->add_option("-o,--output", args->output,
                    "image to write, its format by extension: .png, or .exr with --integrator (its directory is "
                    "created if missing; - for stdout, PNG)")
        ->default_str("render.png")
        ->type_name("FILE");
    cmd->add_flag("-f,--force", args->force, kForceHelp);
    add_threads_option(cmd, args->threads);
    add_light_render_options(cmd, args->light);
    return {cmd, [cmd, args] { return run_render(cmd, *args); }};
}

}  // namespace thicket::cli
