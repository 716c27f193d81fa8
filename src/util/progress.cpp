#include "thicket/util/progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace thicket {

namespace {

constexpr auto kShowAfter = std::chrono::milliseconds(1000);
constexpr auto kRedrawEvery = std::chrono::milliseconds(150);

int terminal_columns() {
    winsize ws{};
    if (ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 20) return ws.ws_col;
    return 80;
}

// One write per line, so a bar update is never interleaved with itself mid-line.
void write_stderr(const std::string& s) {
    std::fwrite(s.data(), 1, s.size(), stderr);
    std::fflush(stderr);
}

}  // namespace

std::string format_si(double value) {
    static const char* const prefixes[] = {"", " k", " M", " G", " T"};
    int p = 0;
    double v = value;
    while (std::fabs(v) >= 1000.0 && p < 4) {
        v /= 1000.0;
        ++p;
    }
    char buf[32];
    if (p == 0 && v == std::floor(v))
        std::snprintf(buf, sizeof buf, "%.0f", v);
    else
        std::snprintf(buf, sizeof buf, std::fabs(v) < 10 ? "%.2f%s" : (std::fabs(v) < 100 ? "%.1f%s" : "%.0f%s"), v,
                      prefixes[p]);
    return buf;
}

std::string format_duration(double seconds) {
    char buf[48];
    if (!(seconds >= 0) || !std::isfinite(seconds)) return "?";
    if (seconds < 0.01)
        std::snprintf(buf, sizeof buf, "%.2f ms", seconds * 1000.0);
    else if (seconds < 1.0)
        std::snprintf(buf, sizeof buf, "%.0f ms", seconds * 1000.0);
    else if (seconds < 60.0)
        std::snprintf(buf, sizeof buf, "%.1f s", seconds);
    else {
        const long total = std::lround(seconds);
        std::snprintf(buf, sizeof buf, "%ld min %02ld s", total / 60, total % 60);
    }
    return buf;
}

bool Progress::terminal_available() {
    if (!isatty(STDERR_FILENO)) return false;
    const char* term = std::getenv("TERM");
    return !(term && std::strcmp(term, "dumb") == 0);
}

Progress::Progress(std::string label, uint64_t total, std::string unit, bool enabled)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total), start_(std::chrono::steady_clock::now()) {
    if (enabled && terminal_available()) thread_ = std::thread([this] { run(); });
}

Progress::~Progress() { abandon(); }

double Progress::elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Progress::run() {
    std::unique_lock<std::mutex> lock(mutex_);
    // Sleep through the first second: quick work never shows a bar.
    if (wake_.wait_until(lock, start_ + kShowAfter, [this] { return stopped_; })) return;
    while (!stopped_) {
        draw();
        wake_.wait_for(lock, kRedrawEvery, [this] { return stopped_; });
    }
}

void Progress::draw() {
    const uint64_t done = std::min(this->done(), total_ > 0 ? total_ : this->done());
    const double secs = elapsed();
    const double rate = secs > 0 ? double(done) / secs : 0.0;
    char buf[160];
    std::string line = "\r";
    const double frac = total_ > 0 ? double(done) / double(total_) : 0.0;
    std::string eta = "?";
    if (rate > 0 && total_ >= done) eta = format_duration(double(total_ - done) / rate);
    std::string also;
    if (!also_unit_.empty() && secs > 0)
        also = "  " + format_si(double(also_.load(std::memory_order_relaxed)) / secs) + " " + also_unit_ + "/s";
    std::snprintf(buf, sizeof buf, " %5.1f%%  %s %s/s%s  ETA %s", 100.0 * frac, format_si(rate).c_str(),
                  unit_.c_str(), also.c_str(), eta.c_str());
    const std::string tail = buf;
    // Never reach the last column: a wrapped line could not be erased by '\r' any more.
    const int columns = terminal_columns() - 1;
    const int bar = std::clamp(columns - int(label_.size() + tail.size()) - 3, 0, 40);
    line += label_;
    if (bar >= 5) {
        const int filled = int(frac * bar + 0.5);
        line += " [";
        line.append(size_t(filled), '#');
        line.append(size_t(bar - filled), '.');
        line += "]";
    }
    line += tail;
    if (int(line.size()) - 1 > columns) line.resize(size_t(columns) + 1);
    line += "\033[K";
    write_stderr(line);
    shown_ = true;
}

void Progress::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopped_) return;
        stopped_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
    if (shown_) write_stderr("\r\033[K");
}

void Progress::finish() { stop(); }
void Progress::abandon() { stop(); }

}  // namespace thicket
