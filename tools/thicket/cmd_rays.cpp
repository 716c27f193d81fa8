// `thicket rays`: writes one of the bench's standard ray sets in the `thicket trace` format, so
// that other libraries can trace exactly the rays the bench measures.
#include <cstdio>
#include <optional>

#include "bench_commands.h"
#include "thicket/bench/ray_sets.h"
#include "thicket/core/error.h"
#include "thicket/util/npy.h"

namespace thicket::cli {

namespace {

struct RaysArgs {
    std::string scene;
    std::string set;
    std::string size = "320x240";
    std::string camera;
    std::string output;
    bool force = false;
    unsigned threads = 0;
};


}  // namespace

std::string vec_text(Vec3 v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%g,%g,%g", double(v.x), double(v.y), double(v.z));
    return buf;
}

void print_view(const RaySetView& view, bool camera_given) {
    std::printf("camera  --camera %s,%s,%g (%s)\n", vec_text(view.camera.position()).c_str(),
                vec_text(view.camera.target()).c_str(), double(view.camera.fov_degrees()),
                camera_given    ? "given"
                : view.interior ? "auto: interior scene, from the centre"
                                : "auto: from outside");
    std::printf("light   %s (%s)\n", vec_text(view.light).c_str(),
                view.interior ? "interior scene: under the ceiling above the centre, or above the bounds if open"
                              : "above the bounds");
}

namespace {

int run_rays(const RaysArgs& args) {
    const std::vector<std::string> names = parse_ray_set_list(args.set);
    if (names.size() != 1) throw Error("--set takes one set name, got '" + args.set + "'");
    RaySetOptions options;
    parse_ray_set_size(args.size, options);
    if (!args.camera.empty()) options.camera = parse_camera(args.camera);
    const std::string output = prepare_output(args.output, args.force, {args.scene});

    const Scene scene = load_scene_verbose(args.scene);
    const std::unique_ptr<Accel> hits_from = build_accel(kRaySetHitSpec, scene);
    const RaySetView view = ray_set_view(scene, *hits_from, options);
    print_view(view, !args.camera.empty());
    const std::vector<RaySet> sets = generate_ray_sets(scene, *hits_from, view, names, options, args.threads);
    const RaySet& set = sets.front();
    std::printf("rays    %s: %zu rays (%s), from a %dx%d image\n", set.name.c_str(), set.rays.size(),
                set.any_hit ? "trace with --any-hit" : "closest hit", options.width, options.height);
    write_npy_f32(output, {set.rays.size(), 8}, ray_matrix(set.rays));
    std::printf("wrote   %s\n", args.output.c_str());
    return 0;
}

}  // namespace

Command add_rays_command(CLI::App& app) {
    auto args = std::make_shared<RaysArgs>();
    CLI::App* cmd = app.add_subcommand("rays", "write one of the bench's standard ray sets of SCENE to a .npy file");
    cmd->footer(
        "View: an interior scene (the centre of the bounds stands in an enclosed space: a 32x24 probe from "
        "there, 60 degree fov along the longer horizontal axis, hits in 90% of its pixels, mostly front faces) is "
        "seen from its centre, with the light 3/4 of the way up to the ceiling above the centre (above the "
        "bounds if nothing is there); any other scene from outside (the render command's auto camera), with "
        "the light above the bounds.\n"
        "Sets: primary (one ray per pixel from the camera), shadow (from every primary hit, offset along the "
        "normal faced toward the camera, to a point light above the scene; any-hit, skipped where the surface "
        "faces away from the light), diffuse (a cosine-weighted direction at every primary hit), random "
        "(WxH rays, uniform origins in the bounds, uniform directions). Fixed seeds: the same scene, size and "
        "camera always give the same bytes.\nOutput: float32 array of shape (N, 8), one ray per row: ox oy oz "
        "dx dy dz tmin tmax, as `thicket trace --rays` reads it (shadow rays with --any-hit).");
    add_scene_argument(cmd, args->scene);
    cmd->add_option("--set", args->set, "ray set: primary, shadow, diffuse or random")->required()->type_name("NAME");
    cmd->add_option("-s,--size", args->size, "image size of the primary set; random has WIDTH*HEIGHT rays")
        ->default_str("320x240")
        ->type_name("WxH");
    cmd->add_option("-c,--camera", args->camera,
                    "camera position and target (and vertical field of view in degrees, default 45); up is +y")
        ->type_name("px,py,pz,tx,ty,tz[,fov]");
    cmd->add_option("-o,--output", args->output, ".npy file to write the rays to (- for stdout)")->required()->type_name("FILE");
    cmd->add_flag("-f,--force", args->force, kForceHelp);
    add_threads_option(cmd, args->threads);
    return {cmd, [args] { return run_rays(*args); }};
}

}  // namespace thicket::cli
