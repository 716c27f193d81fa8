#pragma once
/// Timed passes: one untimed warm-up (caches, page faults, thread start-up), then `reps` timed
/// passes of which the median is reported and the min and max kept as the noise figure.
#include <cstddef>
#include <functional>
#include <utility>
#include <vector>

namespace thicket {

struct PassTimes {
    std::vector<double> seconds;  ///< one entry per timed pass, in run order
    double cpu_seconds = 0.0;     ///< CPU time the whole process used during the timed passes

    /// Wall time of all timed passes together.
    double total() const;
    /// cpu_seconds / (total() * threads): near 1 when `threads` threads ran undisturbed, lower when
    /// other work on the machine took CPU time from the passes.
    double cpu_utilization(double threads) const;
    /// Median pass time (mean of the middle two for an even count); 0 without passes.
    double median() const;
    double min() const;
    double max() const;
};

/// Runs `pass` once untimed, then `reps` (>= 1) times timed with the steady clock (and the process's
/// CPU time, std::clock, around the timed passes); `after_each`
/// (may be empty) is called after every pass, the warm-up included, e.g. to advance a progress bar.
PassTimes time_passes(int reps, const std::function<void()>& pass, const std::function<void()>& after_each = {});

/// Runs `a` and `b` once each untimed, then `reps` (>= 1) times alternately, a before b, timing
/// every pass. Drifts in the machine's speed (other tenants, clock changes), which on a shared
/// machine come and go within seconds, then hit both alike: ratios of paired passes are far
/// steadier than ratios of medians timed a minute apart. `after_each` is called after each pair.
std::pair<PassTimes, PassTimes> time_interleaved(int reps, const std::function<void()>& a,
                                                 const std::function<void()>& b,
                                                 const std::function<void()>& after_each = {});

/// Median of `values` (mean of the middle two for an even count); 0 when empty.
double median(std::vector<double> values);

/// Millions of rays per second for `rays` rays in `seconds` (0 when seconds is not positive).
double mrays_per_second(size_t rays, double seconds);

}  // namespace thicket
