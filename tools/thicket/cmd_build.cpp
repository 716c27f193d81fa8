// `thicket build`: build a structure once and save it for `render --load` / `trace --load`.
#include <cstdio>
#include <filesystem>

#include "common.h"
#include "thicket/core/error.h"
#include "thicket/util/atomic_file.h"

namespace thicket::cli {

namespace {

struct BuildArgs {
    std::string scene;
    AccelChoice accel;
    std::string output;
    bool force = false;
    unsigned threads = 0;
};

int run_build(const BuildArgs& args) {
    const std::optional<AccelSpec> spec = validate_accel_choice(args.accel);
    const std::string output = prepare_output(args.output, args.force, {args.scene});
    const Scene scene = load_scene_verbose(args.scene);
    const std::unique_ptr<Accel> accel = make_accel_verbose(args.accel, spec, scene, args.threads);
    save_accel(*accel, scene, output);
    std::error_code size_ec;
    const auto bytes = std::filesystem::file_size(output, size_ec);
    std::printf("wrote   %s (%s)\n", args.output.c_str(), size_ec ? "?" : format_bytes(double(bytes)).c_str());
    return 0;
}

}  // namespace

Command add_build_command(CLI::App& app) {
    auto args = std::make_shared<BuildArgs>();
    CLI::App* cmd = app.add_subcommand("build", "build a structure over SCENE and save it to a file");
    cmd->footer("The file records the scene's fingerprint: --load refuses it with any other scene. The file is "
                "the same byte for byte whatever --threads is.");
    add_scene_argument(cmd, args->scene);
    add_accel_options(cmd, args->accel, /*accel_required=*/true);
    cmd->add_option("-o,--output", args->output, "file to save the structure to (- for stdout)")->required()->type_name("FILE");
    cmd->add_flag("-f,--force", args->force, kForceHelp);
    add_threads_option(cmd, args->threads);
    return {cmd, [args] { return run_build(*args); }};
}

}  // namespace thicket::cli
