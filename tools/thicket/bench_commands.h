#pragma once
// The bench's subcommands: `thicket rays` writes a standard ray set, `thicket bench` measures
// structures (and Embree, when built with it) on those sets.
#include "common.h"
#include "thicket/bench/ray_sets.h"

namespace thicket::cli {

Command add_rays_command(CLI::App& app);
Command add_bench_command(CLI::App& app);

/// "x,y,z" as --camera spells a point.
std::string vec_text(Vec3 v);
/// Prints the camera and light lines of a ray-set view (`camera_given`: from --camera).
void print_view(const RaySetView& view, bool camera_given);
/// A scene's name in bench and compare tables: a file's name without its folder, a built-in's name.
std::string scene_label(const std::string& path);

}  // namespace thicket::cli
