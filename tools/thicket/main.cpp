// `thicket`: build, inspect, save and use the library's acceleration structures from the shell.
#include <cstdio>
#include <exception>
#include <vector>

#include "bench_commands.h"
#include "common.h"
#include "cost_command.h"
#include "explore_commands.h"
#include "point_commands.h"
#include "thicket/core/error.h"

#ifndef THICKET_VERSION
#define THICKET_VERSION "0.1.0"
#endif

int main(int argc, char** argv) {
    CLI::App app{"thicket " THICKET_VERSION " - ray-tracing acceleration structures: build, inspect, render, trace",
                 "thicket"};
    app.set_version_flag("--version", "thicket " THICKET_VERSION);
    app.require_subcommand(1);
    app.footer("Run `thicket COMMAND --help` for a command's options. Every command that loads a SCENE takes --flatten: "
               "a glTF mesh that several nodes place is copied into one triangle soup instead of instanced.");

    std::vector<thicket::cli::Command> commands;
    try {
        commands = {thicket::cli::add_render_command(app), thicket::cli::add_trace_command(app),
                    thicket::cli::add_closest_command(app), thicket::cli::add_occupancy_command(app),
                    thicket::cli::add_info_command(app), thicket::cli::add_build_command(app),
                    thicket::cli::add_accels_command(app), thicket::cli::add_rays_command(app),
                    thicket::cli::add_bench_command(app), thicket::cli::add_compare_command(app),
                    thicket::cli::add_cost_command(app),
                    thicket::cli::add_explore_command(app), thicket::cli::add_explain_command(app)};
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // Help and --version "fail" with exit code 0; real usage errors get the shell's usual 2.
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }

    try {
        for (const thicket::cli::Command& c : commands)
            if (c.app->parsed()) return c.run();
        return 2;  // unreachable: require_subcommand(1)
    } catch (const std::exception& e) {
        std::fflush(stdout);
        std::fprintf(stderr, "thicket: error: %s\n", e.what());
        return 1;
    }
}
