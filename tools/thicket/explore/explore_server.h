#pragma once
// The HTTP side of `thicket explore`: cpp-httplib carrying requests to a Session, the page's
// files (embedded at build time from web/explore) and Debian's three.js.
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "explore_api.h"

namespace thicket::explore {

/// The files of web/explore by name, embedded by embed_web.cmake.
const std::vector<std::pair<std::string, std::string_view>>& embedded_files();

/// Where three.js is read from: THICKET_THREE_DIR if set, else Debian's libjs-three.
std::string three_js_path();

class Server {
public:
    explicit Server(const Session& session);
    ~Server();
    /// Binds host:port (port 0: a free one) and returns the port; throws Error when it cannot.
    int bind(const std::string& host, int port);
    /// Answers requests until stop(); call after bind().
    void run();
    /// Makes run() return; safe from another thread, and before run() starts.
    void stop();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace thicket::explore
