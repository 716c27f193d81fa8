#include "common.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <unistd.h>

#include "thicket/core/error.h"
#include "thicket/scene/loaders.h"
#include "thicket/util/atomic_file.h"
#include "thicket/util/progress.h"

namespace thicket::cli {

std::string scene_help() {
    return std::string("scene to load: a .ply, .obj, .gltf or .glb file, a .json scene of meshes and shapes "
                       "(sphere, torus, bezier, teapot-patches, subdivision, implicit, blobs, julia, mandelbulb: docs/shapes.md), "
                       "or a built-in scene (") +
           builtin_scene_names() + ")";
}

namespace {
// One subcommand runs per process, so its --flatten can live here: load_scene_verbose() reads it
// and no command has to carry the flag to the load itself.
LoadOptions load_options;
}  // namespace

void add_scene_argument(CLI::App* cmd, std::string& scene) {
    cmd->add_option("SCENE", scene, scene_help())->required()->type_name("SCENE");
    add_flatten_option(cmd);
}

void add_flatten_option(CLI::App* cmd) {
    cmd->add_flag("--flatten", load_options.flatten,
                  "glTF: copy a mesh into one triangle soup for every node that places it (the behaviour before "
                  "instancing) instead of one geometry with an instance per node");
}

void add_accel_options(CLI::App* cmd, AccelChoice& choice, bool accel_required) {
    CLI::Option* accel = cmd->add_option("-a,--accel", choice.spec,
                                         "acceleration structure spec NAME[:key=value,...], e.g. "
                                         "bvh:builder=binned-sah,bins=16 (see `thicket accels`)")
                             ->type_name("SPEC");
    if (accel_required) {
        accel->required();
        return;
    }
    accel->default_str(kDefaultSpec);
    CLI::Option* load = cmd->add_option("--load", choice.load,
                                        "use a structure saved by `thicket build` instead of building one "
                                        "(it must have been built over the same scene)")
                            ->type_name("FILE");
    accel->excludes(load);
    load->excludes(accel);
}

void add_threads_option(CLI::App* cmd, unsigned& threads) {
    cmd->add_option("-j,--threads", threads, "worker threads (0: one per core; at most " + std::to_string(kMaxThreads) + ")")
        ->check(whole_number(0, kMaxThreads))
        ->default_str("0")
        ->type_name("N");
}

CLI::Validator whole_number(uint64_t min, uint64_t max) {
    const std::string range = std::to_string(min) + " to " + std::to_string(max);
    return CLI::Validator(
        [=](std::string& text) -> std::string {
            const std::string quoted = "'" + text + "'";
            if (text.empty()) return "an empty value: expected a whole number from " + range;
            if (text[0] == '-' && text.find_first_not_of("0123456789", 1) == std::string::npos && text.size() > 1)
                return quoted + " is negative: expected a whole number from " + range;
            if (text.find_first_not_of("0123456789") != std::string::npos)
                return quoted + " is not a whole number written in digits (no sign, fraction or exponent): expected " +
                       range;
            uint64_t value = 0;
            const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
            if (ec == std::errc::result_out_of_range || value > max)
                return quoted + " is larger than " + std::to_string(max) + ": expected a whole number from " + range;
            if (ec != std::errc() || end != text.data() + text.size()) return quoted + " is not a whole number";
            if (value < min) return quoted + " is smaller than " + std::to_string(min) + ": expected " + range;
            return {};
        },
        "", "whole number");
}

void refuse_if_given(const CLI::App* cmd, const std::string& option, const std::string& why) {
    const CLI::Option* o = cmd->get_option_no_throw(option);
    if (o && o->count() > 0) throw Error(option + " does not apply here: " + why);
}

std::optional<AccelSpec> validate_accel_choice(const AccelChoice& choice) {
    if (!choice.load.empty()) return std::nullopt;
    return parse_accel_spec(choice.spec);
}

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::string format_bytes(double bytes) {
    static const char* const units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 4) {
        bytes /= 1024.0;
        ++u;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.1f %s", bytes, units[u]);
    return buf;
}

VertexCounts count_bad_vertices(const Scene& scene) {
    VertexCounts c;
    for (const Vec3& p : scene.mesh.positions) {
        const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
        c.nonfinite += !finite;
        c.large += finite && (std::fabs(p.x) > kLargeCoordinate || std::fabs(p.y) > kLargeCoordinate ||
                              std::fabs(p.z) > kLargeCoordinate);
    }
    return c;
}

Scene load_scene_verbose(const std::string& path) {
    std::error_code ec;
    if (path == "spheres" && !std::filesystem::exists(path, ec))
        throw Error("spheres: the lecture's generated scene (--spheres N spheres, --lights N lights) exists only "
                    "in `thicket render` and `thicket cost`; this command loads files and the built-in scenes (" +
                    std::string(builtin_scene_names()) + ")");
    const auto start = std::chrono::steady_clock::now();
    Scene scene = load_scene(path, load_options);
    const VertexCounts bad = count_bad_vertices(scene);
    if (bad.nonfinite)
        std::fprintf(stderr, "%s: warning: %zu vertices are NaN or infinite (beyond float's 3.4e38); triangles using them are never hit\n",
                     path.c_str(), bad.nonfinite);
    if (bad.large)
        std::fprintf(stderr, "%s: warning: %zu vertices lie beyond 1e18; float arithmetic overflows there and hits may be lost\n",
                     path.c_str(), bad.large);
    const std::string shapes = scene.has_shapes() ? ", " + std::to_string(scene.shapes.size()) + " shapes" : "";
    std::printf("scene   %s: %zu triangles%s, %zu vertices, loaded in %s\n", scene.name.c_str(),
                scene.mesh.triangle_count(), shapes.c_str(), scene.mesh.positions.size(),
                format_duration(ms_since(start) / 1000).c_str());
    return scene;
}

std::vector<AskedSpec> parse_accel_specs(const std::vector<std::string>& asked) {
    std::vector<std::string> expanded;
    for (const std::string& s : asked) {
        if (s == "all") {
            const std::vector<std::string> all = all_accel_variants();
            expanded.insert(expanded.end(), all.begin(), all.end());
        } else {
            expanded.push_back(s);
        }
    }
    std::vector<AskedSpec> specs;
    for (const std::string& s : expanded) {
        AccelSpec parsed = parse_accel_spec(s);
        if (std::none_of(specs.begin(), specs.end(), [&](const AskedSpec& a) { return a.text == s; }))
            specs.push_back({s, std::move(parsed)});
    }
    return specs;
}

std::vector<std::string> expand_accel_specs(const std::vector<std::string>& asked) {
    std::vector<std::string> texts;
    for (AskedSpec& a : parse_accel_specs(asked)) texts.push_back(std::move(a.text));
    return texts;
}

std::string load_average() {
    std::FILE* f = std::fopen("/proc/loadavg", "r");
    double one = 0.0;
    const bool ok = f && std::fscanf(f, "%lf", &one) == 1;
    if (f) std::fclose(f);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", one);
    return ok ? buf : "unknown";
}

std::unique_ptr<Accel> make_accel_verbose(const AccelChoice& choice, const std::optional<AccelSpec>& spec,
                                          const Scene& scene, unsigned threads) {
    std::unique_ptr<Accel> accel;
    std::string how;
    if (!choice.load.empty()) {
        const auto start = std::chrono::steady_clock::now();
        accel = load_accel(choice.load, scene);
        how = "loaded from " + choice.load + " in " + format_duration(ms_since(start) / 1000);
    } else {
        accel = build_accel(spec.value(), scene, threads);
    }
    const AccelStats st = accel->stats();
    if (how.empty()) how = "built in " + format_duration(st.build_ms / 1000);
    std::printf("accel   %s: %s, %zu nodes (%zu leaves, depth %zu), %s\n", accel->spec().c_str(), how.c_str(),
                st.nodes, st.leaves, st.max_depth, format_bytes(double(st.bytes)).c_str());
    std::fflush(stdout);
    return accel;
}

void refuse_overwrite(const std::string& path, bool force) {
    if (path.empty()) return;
    const OutputTarget target = resolve_output(path);
    if (target.kind == OutputTarget::Regular && !force) throw Error(path + " already exists (use --force to overwrite it)");
}

void refuse_output_is_input(const std::string& output, const std::vector<std::string>& inputs) {
    if (output.empty() || output == "-") return;
    for (const std::string& in : inputs) {
        std::error_code ec;
        if (!in.empty() && std::filesystem::equivalent(output, in, ec) && !ec)
            throw Error(output + " is the input " + in + ": writing it would destroy the input; choose another output");
    }
}

std::string prepare_output(const std::string& output, bool force, const std::vector<std::string>& inputs) {
    refuse_output_is_input(output, inputs);
    refuse_overwrite(output, force);
    if (output != "-") return output;
    // The data goes to the original stdout, through a descriptor of its own; the progress lines
    // every command prints go to stderr from here on.
    std::fflush(stdout);
    const int data = ::dup(STDOUT_FILENO);
    if (data < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) throw Error("-: cannot redirect stdout");
    return "/dev/fd/" + std::to_string(data);
}

}  // namespace thicket::cli
