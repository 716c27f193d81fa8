#include "thicket/bench/timing.h"

#include <algorithm>
#include <chrono>
#include <ctime>

#include "thicket/core/error.h"

namespace thicket {

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t m = values.size() / 2;
    return values.size() % 2 ? values[m] : 0.5 * (values[m - 1] + values[m]);
}

double PassTimes::median() const { return thicket::median(seconds); }

double PassTimes::total() const {
    double sum = 0.0;
    for (double s : seconds) sum += s;
    return sum;
}

double PassTimes::cpu_utilization(double threads) const {
    const double wall = total() * threads;
    return wall > 0.0 ? cpu_seconds / wall : 1.0;
}

double PassTimes::min() const { return seconds.empty() ? 0.0 : *std::min_element(seconds.begin(), seconds.end()); }
double PassTimes::max() const { return seconds.empty() ? 0.0 : *std::max_element(seconds.begin(), seconds.end()); }

namespace {

// Runs one pass, appending its wall time and the process's CPU time to `times`.
void timed_pass(const std::function<void()>& pass, PassTimes& times) {
    const std::clock_t cpu_start = std::clock();
    const auto start = std::chrono::steady_clock::now();
    pass();
    times.seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    times.cpu_seconds += double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
}

void check_reps(int reps) {
    if (reps < 1) throw Error("time_passes: at least one timed pass is needed, got " + std::to_string(reps));
}

}  // namespace

PassTimes time_passes(int reps, const std::function<void()>& pass, const std::function<void()>& after_each) {
    check_reps(reps);
    pass();
    if (after_each) after_each();
    PassTimes times;
    for (int r = 0; r < reps; ++r) {
        timed_pass(pass, times);
        if (after_each) after_each();
    }
    return times;
}

std::pair<PassTimes, PassTimes> time_interleaved(int reps, const std::function<void()>& a,
                                                 const std::function<void()>& b,
                                                 const std::function<void()>& after_each) {
    check_reps(reps);
    a();
    b();
    if (after_each) after_each();
    std::pair<PassTimes, PassTimes> times;
    for (int r = 0; r < reps; ++r) {
        timed_pass(a, times.first);
        timed_pass(b, times.second);
        if (after_each) after_each();
    }
    return times;
}

double mrays_per_second(size_t rays, double seconds) { return seconds > 0.0 ? double(rays) / seconds * 1e-6 : 0.0; }

}  // namespace thicket
