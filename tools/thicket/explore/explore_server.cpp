// cpp-httplib glue: routes /api/* to the Session, serves the embedded page and three.js.
#include "explore_server.h"

#include <httplib.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "explore_json.h"
#include "thicket/core/error.h"

namespace thicket::explore {

namespace {

const char* content_type(const std::string& name) {
    const auto ends = [&](const char* ext) {
        const std::string e = ext;
        return name.size() >= e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
    };
    if (ends(".html")) return "text/html; charset=utf-8";
    if (ends(".js")) return "text/javascript; charset=utf-8";
    if (ends(".css")) return "text/css; charset=utf-8";
    if (ends(".png")) return "image/png";
    return "application/octet-stream";
}

void send_error(httplib::Response& res, int status, const std::string& message) {
    const Response r = error_response(status, message);
    res.status = status;
    res.set_content(r.body, r.content_type.c_str());
}

}  // namespace

std::string three_js_path() {
    if (const char* dir = std::getenv("THICKET_THREE_DIR"); dir && *dir) return std::string(dir) + "/three.min.js";
    return "/usr/share/javascript/three/build/three.min.js";
}

struct Server::Impl {
    const Session& session;
    httplib::Server http;
    std::atomic<bool> stopping{false};
    explicit Impl(const Session& s) : session(s) {}
};

Server::Server(const Session& session) : impl_(std::make_unique<Impl>(session)) {
    httplib::Server& http = impl_->http;
    const Session& s = session;
    // Bodies up to 16x the limit are read whole and refused by the session (413), so the
    // connection stays in step; httplib refuses larger ones itself without reading them, and
    // its connection then cannot be reused (the client must reconnect).
    http.set_payload_max_length(16 * kMaxBodyBytes);
    http.set_keep_alive_max_count(1000);
    http.set_read_timeout(5, 0);
    // /api/*: every method reaches the session, which names the one each request takes.
    const auto api = [&s](const httplib::Request& req, httplib::Response& res) {
        const Response r = s.handle(req.method, req.path, req.body);
        res.status = r.status;
        res.set_content(r.body, r.content_type.c_str());
    };
    http.Get("/api/.*", api);
    http.Post("/api/.*", api);
    http.Put("/api/.*", api);
    http.Delete("/api/.*", api);
    http.Get("/three.min.js", [](const httplib::Request&, httplib::Response& res) {
        // The one file besides the scene this server reads: a fixed path, never one from the request.
        const std::string path = three_js_path();
        std::ifstream in(path, std::ios::binary);
        if (!in) return send_error(res, 404, path + " not found: install Debian's libjs-three (scripts/setup) "
                                                    "or set THICKET_THREE_DIR");
        std::ostringstream text;
        text << in.rdbuf();
        res.set_content(text.str(), "text/javascript; charset=utf-8");
    });
    http.Get("/(.*)", [](const httplib::Request& req, httplib::Response& res) {
        const std::string name = req.matches[1].str().empty() ? "index.html" : req.matches[1].str();
        for (const auto& [file, bytes] : embedded_files())
            if (file == name) return res.set_content(std::string(bytes), content_type(file));
        send_error(res, 404, "no such page: /" + name.substr(0, 200));
    });
    // httplib's own refusals (an oversized body: 413, a request it cannot parse: 400) get a JSON
    // reason like the session's.
    http.set_error_handler([](const httplib::Request&, httplib::Response& res) {
        if (res.body.empty()) send_error(res, res.status, "request refused by the HTTP layer (status " +
                                                              std::to_string(res.status) + ")");
    });
    http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        send_error(res, 500, "internal error");
    });
}

Server::~Server() = default;

int Server::bind(const std::string& host, int port) {
    int bound = port;
    if (port == 0)
        bound = impl_->http.bind_to_any_port(host);
    else if (!impl_->http.bind_to_port(host, port))
        bound = -1;
    if (bound <= 0)
        throw Error("explore: cannot listen on " + host + ":" + std::to_string(port) +
                    (port == 0 ? std::string(" (not one of this machine's addresses?)")
                               : std::string(" (port in use, or not one of this machine's addresses? --port 0 takes a free port)")));
    return bound;
}

void Server::run() {
    if (!impl_->stopping) impl_->http.listen_after_bind();
}

void Server::stop() {
    impl_->stopping = true;
    impl_->http.stop();
}

}  // namespace thicket::explore
