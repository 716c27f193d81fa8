#pragma once
// `thicket render --integrator path|whitted`: the light-transport renders, kept apart from the
// preview views of cmd_render.cpp.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

#include "common.h"
#include "thicket/render/film.h"

namespace thicket::cli {

struct LightRenderArgs {
    std::string integrator;      // empty: a preview view (--view) instead
    uint32_t spp = 16;
    uint64_t seed = 0;
    double time = 0.0;           // > 0: progressive passes until this many seconds have passed
    double exposure = 1.0;       // read as double so that 1e39 and 1e-50 are told apart from text
    uint32_t max_depth = 64;
    uint32_t spheres = 1000;     // the built-in `spheres` scene
    uint32_t lights = 4;
    uint64_t scene_seed = 1;
};

/// Adds --integrator, --spp, --seed, --time, --exposure, --max-depth and the `spheres` scene's
/// --spheres, --lights, --scene-seed to `cmd`.
void add_light_render_options(CLI::App* cmd, LightRenderArgs& args);

/// Refuses (throws Error naming the option) --integrator's options when there is no --integrator
/// (the preview views take no samples), an empty --integrator, and the `spheres` scene's options
/// on any other scene. `cmd` is the render command, `scene_name` its SCENE.
void refuse_light_options_that_do_not_apply(const CLI::App* cmd, const std::string& scene_name,
                                            const LightRenderArgs& args);

/// The image format of a render's -o: by extension (.png, .exr); "-" and special files such as
/// /dev/null without an extension are PNG. Throws Error naming the extension otherwise.
ImageFormat output_image_format(const std::string& output);

/// Renders `scene_name` with args.integrator (non-empty) to `output` (.png or .exr); `camera_text` as
/// --camera (empty: the scene's own camera, else the automatic one). Returns the exit code;
/// throws Error naming the bad option or value.
int run_light_render(const std::string& scene_name, const AccelChoice& accel, int width, int height,
                     const std::string& camera_text, const std::string& output, unsigned threads,
                     const LightRenderArgs& args);

}  // namespace thicket::cli
