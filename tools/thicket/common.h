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

/// The --accel SPEC / --load FILE pair (mutually exclusive); without either, kDefaultSpec.
struct AccelChoice {
    std::string spec = kDefaultSpec;
    std::string load;
};

/// Help text of the SCENE argument.
std::string scene_help();
/// Adds the SCENE positional argument, and --flatten (add_flatten_option).
void add_scene_argument(CLI::App* cmd, std::string& scene);
/// Adds --flatten: glTF scenes are loaded as one triangle soup with a copy of a mesh per node
/// that places it (LoadOptions::flatten) by every later load_scene_verbose() of the process.
void add_flatten_option(CLI::App* cmd);
/// Adds --accel and --load; `accel_required` makes --accel mandatory (and omits --load).
void add_accel_options(CLI::App* cmd, AccelChoice& choice, bool accel_required = false);
/// Adds --threads N (0, the default, uses every core; at most kMaxThreads).
void add_threads_option(CLI::App* cmd, unsigned& threads);
/// Largest --threads: each worker costs a stack and a start-up, and beyond a few per core they
/// only add that cost (100,000 would be taken at its word and reported).
inline constexpr unsigned kMaxThreads = 1024;

/// A CLI11 check run on the option's text before conversion: a whole number written in digits
/// (no sign, fraction or exponent) within [min, max]. Without it CLI11 wraps -1 to 2^64 - 1 and
/// saturates 1e23; with it the error says which of those the text is.
CLI::Validator whole_number(uint64_t min, uint64_t max);

/// Throws Error "OPTION does not apply here: WHY" when `option` (its long name, e.g. "--spp") was
/// given on cmd's command line: an option that would be silently ignored is refused instead.
void refuse_if_given(const CLI::App* cmd, const std::string& option, const std::string& why);

/// Parses --accel's spec before any slow work, so a typo fails at once (throws Error). Returns
/// the parsed spec for make_accel_verbose() (the spec is parsed once); nullopt with --load.
std::optional<AccelSpec> validate_accel_choice(const AccelChoice& choice);
/// Loads the scene and prints one line about it (for the name `spheres`, when no such file exists,
/// throws Error saying which commands generate that scene), and a warning on stderr when vertices are NaN,
/// infinite (1e40 in a file is infinite as a float) or beyond kLargeCoordinate.
Scene load_scene_verbose(const std::string& path);

/// Coordinates beyond 1e18 in magnitude: ray/triangle products of such numbers overflow float
/// (their squares pass 3.4e38), so hits there are lost; the CLI warns about them.
inline constexpr float kLargeCoordinate = 1e18f;
/// Vertices of `scene` that are NaN or infinite, and those finite but beyond kLargeCoordinate.
struct VertexCounts {
    size_t nonfinite = 0, large = 0;
};
VertexCounts count_bad_vertices(const Scene& scene);
/// Builds (or loads with --load) the structure on up to `threads` threads (0: every core) and
/// prints one line about it. `spec`: validate_accel_choice()'s result for `choice` (what is
/// built: the spec is not parsed again).
std::unique_ptr<Accel> make_accel_verbose(const AccelChoice& choice, const std::optional<AccelSpec>& spec,
                                          const Scene& scene, unsigned threads);

/// "12.3 KiB" style byte counts.
std::string format_bytes(double bytes);

/// Throws Error "PATH already exists (use --force to overwrite it)" when PATH is an existing
/// regular file (through symlinks) and not `force`; an empty path (no such output asked for), a
/// new path and a special file (/dev/null, a FIFO, "-") pass. Also throws resolve_output()'s
/// errors (a directory, a read-only file). Call it before the slow work.
void refuse_overwrite(const std::string& path, bool force);
/// Throws Error "OUTPUT is the input INPUT" when `output` names the same file as one of `inputs`
/// (through links; inputs that do not exist or are empty are skipped): writing it would destroy
/// the input, --force or not.
void refuse_output_is_input(const std::string& output, const std::vector<std::string>& inputs);
/// The checks above for a command's one output: refuse_output_is_input, then refuse_overwrite.
/// For "-" (stdout) it also sends the command's messages to stderr from now on, so that stdout
/// carries only the data, and returns the path to write the data to; otherwise returns `output`.
std::string prepare_output(const std::string& output, bool force, const std::vector<std::string>& inputs);
/// Largest --reps, --build-reps (1000 timed passes) and --rounds (100) the bench and compare take.
inline constexpr int kMaxReps = 1000;
inline constexpr int kMaxRounds = 100;
/// The help text of --force for a command whose output is FILE.
inline constexpr const char* kForceHelp = "overwrite the output file if it exists (special files such as /dev/null, "
                                          "a FIFO or - for stdout are written without it)";
/// One spec as it was asked for (what tables and tracers are named by) and parsed.
struct AskedSpec {
    std::string text;
    AccelSpec spec;
};
/// `asked` with every `all` replaced by every registered variant (all_accel_variants()),
/// duplicates dropped (the first kept), each spec parsed so that a typo throws Error before any
/// slow work.
std::vector<AskedSpec> parse_accel_specs(const std::vector<std::string>& asked);
/// The texts of parse_accel_specs(asked).
std::vector<std::string> expand_accel_specs(const std::vector<std::string>& asked);
/// The 1-minute load average (Linux), or "unknown": other work on the machine is the first
/// thing to rule out when timings look noisy.
std::string load_average();
/// Milliseconds since `start` (a steady_clock time point).
double ms_since(std::chrono::steady_clock::time_point start);

}  // namespace thicket::cli
