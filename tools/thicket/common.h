#pragma once
// Pieces shared by the `thicket` subcommands: scene and structure loading with timings, option
// parsing helpers, and the Command type each cmd_*.cpp registers.
#include <CLI/CLI.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <vector>
#include <string>

#include "thicket/accel/registry.h"
#include "thicket/scene/scene.h"

namespace thicket::cli {

/// A registered subcommand: its CLI11 app and what to run when it was chosen (returns the exit code).
struct Command {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

Command add_render_command(CLI::App& app);
Command add_trace_command(CLI::App& app);
Command add_closest_command(CLI::App& app);
Command add_info_command(CLI::App& app);
Command add_build_command(CLI::App& app);
Command add_accels_command(CLI::App& app);
Command add_compare_command(CLI::App& app);

/// The --accel SPEC / --load FILE pair (mutually exclusive).
/// The structure `render`, `trace` and `info` use without --accel: the fastest.
inline constexpr const char* kDefaultAccel = "bvh8";

struct AccelChoice {
    std::string spec = kDefaultAccel;
    std::string load;
};

/// Help text of the SCENE argument.
std::string scene_help();
/// Adds the SCENE positional argument.
void add_scene_argument(CLI::App* cmd, std::string& scene);
/// Adds --accel and --load; `accel_required` makes --accel mandatory (and omits --load).
void add_accel_options(CLI::App* cmd, AccelChoice& choice, bool accel_required = false);
/// Adds --threads N (0, the default, uses every core).
void add_threads_option(CLI::App* cmd, unsigned& threads);

/// Parses --accel's spec before any slow work, so a typo fails at once (throws Error). Returns
/// the parsed spec for make_accel_verbose() (the spec is parsed once); nullopt with --load.
std::optional<AccelSpec> validate_accel_choice(const AccelChoice& choice);
/// Loads the scene and prints one line about it.
Scene load_scene_verbose(const std::string& path);
/// Builds (or loads with --load) the structure on up to `threads` threads (0: every core) and
/// prints one line about it. `spec`: validate_accel_choice()'s result for `choice`.
std::unique_ptr<Accel> make_accel_verbose(const AccelChoice& choice, const std::optional<AccelSpec>& spec,
                                          const Scene& scene, unsigned threads);

/// "12.3 KiB" style byte counts.
std::string format_bytes(double bytes);

/// Throws Error "PATH already exists (use --force to overwrite it)" unless `force`, the path is
/// empty (no such output asked for), or nothing is there. Call it before the slow work.
void refuse_overwrite(const std::string& path, bool force);
/// `asked` with every `all` replaced by every registered variant (all_accel_variants()),
/// duplicates dropped (the first kept), each spec parsed so that a typo throws Error before any
/// slow work.
std::vector<std::string> expand_accel_specs(const std::vector<std::string>& asked);
/// The 1-minute load average (Linux), or "unknown": other work on the machine is the first
/// thing to rule out when timings look noisy.
std::string load_average();
/// Milliseconds since `start` (a steady_clock time point).
double ms_since(std::chrono::steady_clock::time_point start);

}  // namespace thicket::cli
