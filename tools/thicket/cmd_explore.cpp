// `thicket explore` (a local web page over a scene's structures, docs/explore.md) and `thicket
// explain` (one ray's traversal as JSON, through the same recording path as the page).
#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <thread>

#include "common.h"
#include "explore_api.h"
#include "explore_commands.h"
#include "explore_server.h"
#include "thicket/core/error.h"

namespace thicket::cli {

namespace {

struct ExploreArgs {
    std::string scene;
    std::vector<std::string> accels;
    std::string host = "127.0.0.1";
    int port = 8080;
    unsigned threads = 0;
};

/// Builds each asked structure once (duplicates dropped, typos refused before loading).
std::vector<std::unique_ptr<Accel>> build_all(const std::vector<std::string>& asked, const Scene& scene,
                                              unsigned threads) {
    std::vector<std::unique_ptr<Accel>> out;
    for (const AskedSpec& a : parse_accel_specs(asked.empty() ? std::vector<std::string>{"bvh"} : asked)) {
        AccelChoice choice;
        choice.spec = a.text;
        out.push_back(make_accel_verbose(choice, a.spec, scene, threads));
    }
    return out;
}

int run_explore(const ExploreArgs& args) {
    parse_accel_specs(args.accels);  // a typo fails before the scene is read
    // SIGINT and SIGTERM go to one thread, which stops the server: blocked here, before any other
    // thread exists, so that no worker inherits them unblocked and dies of them.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);
    std::atomic<explore::Server*> server{nullptr};
    std::atomic<bool> done{false};
    std::thread watcher([&] {
        int sig = 0;
        sigwait(&signals, &sig);
        if (done) return;
        if (explore::Server* s = server.load()) {
            std::fprintf(stderr, "explore: stopping (%s)\n", sig == SIGINT ? "interrupt" : "terminate");
            s->stop();
        } else {
            std::fprintf(stderr, "explore: interrupted before the server started\n");
            std::_Exit(130);
        }
    });
    struct Join {  // the watcher ends on its signal, or on the one sent here when the server ends otherwise
        std::thread& t;
        std::atomic<bool>& done;
        ~Join() {
            done = true;
            pthread_kill(t.native_handle(), SIGTERM);
            t.join();
        }
    } join{watcher, done};

    Scene scene = load_scene_verbose(args.scene);
    std::vector<std::unique_ptr<Accel>> accels = build_all(args.accels, scene, args.threads);
    const explore::Session session(std::move(scene), std::move(accels), args.threads);
    explore::Server http(session);
    const int port = http.bind(args.host, args.port);
    const std::string shown_host = args.host.find(':') != std::string::npos ? "[" + args.host + "]" : args.host;
    std::printf("explore http://%s:%d/  (Ctrl-C stops)\n", shown_host.c_str(), port);
    std::fflush(stdout);
    server = &http;
    http.run();
    server = nullptr;
    std::printf("explore stopped\n");
    return 0;
}

struct ExplainArgs {
    std::string scene;
    AccelChoice accel;
    std::string ray;
    bool any = false;
    unsigned threads = 0;
};

/// "ox,oy,oz,dx,dy,dz[,tmin,tmax]" as a ray; Error naming the text when it is not one.
Ray parse_ray_text(const std::string& text) {
    float r[8] = {0, 0, 0, 0, 0, 0, 0, kInfinity};
    std::stringstream in(text);
    std::string part;
    int n = 0;
    while (std::getline(in, part, ',')) {
        char* end = nullptr;
        const float v = n < 8 ? std::strtof(part.c_str(), &end) : 0.0f;
        if (n >= 8 || part.empty() || end == part.c_str() || *end != '\0')
            throw Error("--ray '" + text + "': expected 6 or 8 comma-separated numbers (ox,oy,oz,dx,dy,dz[,tmin,tmax])");
        r[n++] = v;
    }
    if (n != 6 && n != 8)
        throw Error("--ray '" + text + "': " + std::to_string(n) + " numbers; expected 6 or 8 (ox,oy,oz,dx,dy,dz[,tmin,tmax])");
    Ray ray;
    if (!make_ray(r, ray))
        throw Error("--ray '" + text + "' is not a ray: non-finite origin or direction, zero direction or tmin > tmax");
    return ray;
}

/// While alive, what the process prints to stdout goes to stderr (the tool's usual scene and
/// build lines), so that stdout carries the JSON alone.
struct StdoutToStderr {
    int saved;
    StdoutToStderr() {
        std::fflush(stdout);
        saved = dup(1);
        dup2(2, 1);
    }
    ~StdoutToStderr() {
        std::fflush(stdout);
        dup2(saved, 1);
        close(saved);
    }
};

int run_explain(const ExplainArgs& args) {
    const Ray ray = parse_ray_text(args.ray);
    const std::optional<AccelSpec> spec = validate_accel_choice(args.accel);
    std::optional<Scene> scene;
    std::unique_ptr<Accel> accel;
    {
        StdoutToStderr quiet;
        scene = load_scene_verbose(args.scene);
        accel = make_accel_verbose(args.accel, spec, *scene, args.threads);
    }
    std::printf("%s\n", explore::explain_ray(*accel, *scene, ray, args.any).c_str());
    return 0;
}

}  // namespace

Command add_explore_command(CLI::App& app) {
    auto args = std::make_shared<ExploreArgs>();
    CLI::App* cmd = app.add_subcommand("explore", "serve a web page that draws SCENE's structures and replays rays through them");
    cmd->footer("Builds each --accel structure once (bvh when none is given), then answers the page at the printed "
                "URL until Ctrl-C (SIGINT or SIGTERM). Only SCENE is read, and three.js from Debian's libjs-three "
                "(/usr/share/javascript/three, or $THICKET_THREE_DIR). The page shows the mesh (above 200,000 "
                "triangles every k-th one), the nodes by depth, a heatmap of nodes visited or primitives tested per "
                "pixel computed with the real structure (one scale for two structures), one ray's traversal step by "
                "step, and `thicket info`'s figures. Requests are bounded (64 KiB bodies, 512x512-pixel heatmaps, "
                "50,000 boxes, 20,000 recorded steps) and refused with a 4xx JSON error beyond. docs/explore.md.");
    add_scene_argument(cmd, args->scene);
    cmd->add_option("-a,--accel", args->accels, "structure spec to serve, repeatable (e.g. --accel bvh --accel grid); "
                                                "bvh and grid record their steps and draw their nodes")
        ->type_name("SPEC");
    cmd->add_option("--host", args->host, "address to listen on; another than 127.0.0.1 exposes the page to the network")
        ->default_str("127.0.0.1")
        ->type_name("ADDR");
    cmd->add_option("--port", args->port, "port to listen on (0: a free one, printed)")
        ->check(whole_number(0, 65535))
        ->default_str("8080")
        ->type_name("N");
    add_threads_option(cmd, args->threads);
    return {cmd, [args] { return run_explore(*args); }};
}

Command add_explain_command(CLI::App& app) {
    auto args = std::make_shared<ExplainArgs>();
    CLI::App* cmd = app.add_subcommand("explain", "print one ray's traversal through a structure as JSON");
    cmd->footer("Output (stdout; the scene and build lines go to stderr): {structure, query, ray, detailed, nodes, "
                "prims, dropped, hit, steps} (and `occluded` with --any-hit). Each step is {kind: enter|cull|skip|prim, "
                "id, t}: a node, cell or tetrahedron entered at t, a node whose box was tested and missed (t null), a "
                "node entered earlier and dropped unvisited because a nearer hit was found since (skip, t its entry), "
                "a primitive tested (t: the closest hit so far; with --any-hit the ray's tmax). Nodes carry their box, "
                "tetrahedra their corners, triangles theirs. `detailed` is false for structures that report only the "
                "totals (all but bvh, bvh8, grid and tetra for now; with --any-hit, all but bvh, grid and tetra). The "
                "same path as `thicket explore`'s trace request.");
    add_scene_argument(cmd, args->scene);
    add_accel_options(cmd, args->accel);
    cmd->add_option("--ray", args->ray, "the ray: ox,oy,oz,dx,dy,dz[,tmin,tmax]")->required()->type_name("RAY");
    cmd->add_flag("--any-hit", args->any, "the any-hit (shadow) query: stops at the first hit, says whether the ray is occluded");
    add_threads_option(cmd, args->threads);
    return {cmd, [args] { return run_explain(*args); }};
}

}  // namespace thicket::cli
