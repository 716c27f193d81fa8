#pragma once
/// A progress bar on stderr for long loops. It stays invisible for quick work and in logs: the bar
/// is drawn only when stderr is a terminal and the work has run longer than about a second.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

namespace thicket {

class Progress {
public:
    /// Starts timing `total` units of work (`unit` is a plural noun such as "rays", for the rate).
    /// `enabled = false` never draws anything (e.g. for --quiet).
    Progress(std::string label, uint64_t total, std::string unit, bool enabled = true);
    /// Same as abandon() unless finish() was called.
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Records n more units done; thread-safe and cheap (one atomic add), callable from workers.
    void advance(uint64_t n = 1) { done_.fetch_add(n, std::memory_order_relaxed); }
    /// Also shows the rate of a second count (e.g. "rays" while the bar counts samples); call
    /// before the work starts. Not thread-safe; count_also() is.
    void show_rate_of(std::string unit) { also_unit_ = std::move(unit); }
    /// Records n more units of the second count (show_rate_of); one atomic add.
    void count_also(uint64_t n) { also_.fetch_add(n, std::memory_order_relaxed); }
    /// Units recorded so far.
    uint64_t done() const { return done_.load(std::memory_order_relaxed); }
    /// Seconds since construction.
    double elapsed() const;
    /// Ends successfully: a shown bar is erased (the caller reports the result), leaving the cursor
    /// at the start of a clean line; nothing is printed if no bar was shown. Idempotent.
    void finish();
    /// Ends after a failure; the same as finish() today, kept apart so that callers say which.
    void abandon();

    /// Whether the bar is drawn at all in this process (stderr is a terminal, TERM is not "dumb").
    static bool terminal_available();

private:
    void run();
    void draw();
    void stop();

    std::string label_, unit_;
    uint64_t total_;
    std::atomic<uint64_t> done_{0};
    std::string also_unit_;
    std::atomic<uint64_t> also_{0};
    std::chrono::steady_clock::time_point start_;
    bool shown_ = false;    // only touched by the drawing thread, then by stop() after joining it
    bool stopped_ = false;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::thread thread_;
};

/// "1.23 M" style rendering of a count or rate with SI prefixes (k, M, G), for messages.
std::string format_si(double value);
/// "850 ms", "12.3 s" or "2 min 05 s": a duration for humans.
std::string format_duration(double seconds);

}  // namespace thicket
