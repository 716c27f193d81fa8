#include "thicket/bench/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "thicket/bench/scene_sizes.h"
#include "thicket/bench/timing.h"
#include "thicket/core/error.h"

namespace thicket {

std::vector<size_t> default_growth_sizes(size_t max_size) {
    if (max_size < 1) throw Error("the largest growth size must be at least 1");
    std::vector<size_t> sizes;
    for (size_t decade = 1000; decade < max_size && decade <= kMaxSceneSize; decade *= 10)
        for (size_t s : {decade, 3 * decade})
            if (s < max_size) sizes.push_back(s);
    sizes.push_back(max_size);
    return sizes;
}

std::vector<size_t> parse_size_list(std::string_view text) {
    std::vector<size_t> sizes;
    size_t begin = 0;
    while (true) {
        const size_t comma = text.find(',', begin);
        std::string item(text.substr(begin, comma == std::string_view::npos ? std::string_view::npos : comma - begin));
        item.erase(0, item.find_first_not_of(" \t"));
        item.erase(item.find_last_not_of(" \t") + 1);
        char* end = nullptr;
        const double v = item.empty() ? 0.0 : std::strtod(item.c_str(), &end);
        if (item.empty() || end != item.c_str() + item.size() || !std::isfinite(v) || v != std::floor(v) || v < 1 ||
            v > double(kMaxSceneSize))
            throw Error("size '" + item + "' in '" + std::string(text) + "' must be a whole number from 1 to " +
                        std::to_string(kMaxSceneSize) + " (e.g. 1000 or 1e5)");
        sizes.push_back(size_t(v));
        if (comma == std::string_view::npos) break;
        begin = comma + 1;
    }
    std::sort(sizes.begin(), sizes.end());
    sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
    return sizes;
}

std::vector<std::string> default_compare_specs() {
    std::vector<std::string> specs;
    for (const AccelInfo& info : accel_registry())
        if (info.partitioning != Partitioning::None) specs.push_back(info.name);
    return specs;
}

Partitioning spec_partitioning(std::string_view spec) {
    const AccelInfo* info = find_accel(spec.substr(0, spec.find(':')));
    return info ? info->partitioning : Partitioning::Unknown;
}

Growth measure_growth(const std::string& spec, std::span<const Scene> sized, const GrowthOptions& options,
                      const std::function<void(const GrowthPoint&)>& after_size) {
    if (options.max_builds < 1) throw Error("builds per size must be at least 1");
    Growth growth;
    for (const Scene& scene : sized) {
        const size_t n = scene.primitive_count();
        if (options.build_budget_s > 0.0 && !growth.points.empty()) {
            // Predict from the last build, growing at least linearly: a noisy flat step between two
            // tiny sizes must not promise a cheap next size.
            const GrowthPoint& last = growth.points.back();
            double slope = 1.0;
            if (growth.points.size() >= 2) {
                const GrowthPoint& prev = growth.points[growth.points.size() - 2];
                if (prev.build_ms > 0.0 && last.build_ms > 0.0 && last.n > prev.n)
                    slope = std::max(slope, std::log(last.build_ms / prev.build_ms) /
                                                std::log(double(last.n) / double(prev.n)));
            }
            const double predicted_ms = last.build_ms * std::pow(double(n) / double(last.n), slope);
            if (predicted_ms > options.build_budget_s * 1000.0) {
                growth.stopped_at = n;
                growth.predicted_s = predicted_ms / 1000.0;
                break;
            }
        }
        std::vector<double> times;
        double total = 0.0;
        while (int(times.size()) < options.max_builds && (times.empty() || total < options.repeat_budget_ms)) {
            // One thread: the growth exponent is the algorithm's, not the machine's parallelism.
            const double ms = options.build ? options.build(spec, scene)
                                            : build_accel(spec, scene, 1)->build_ms();  // destroyed before the next build
            times.push_back(ms);
            total += ms;
        }
        growth.points.push_back({n, median(times), int(times.size())});
        if (after_size) after_size(growth.points.back());
    }
    std::vector<double> ns, ms;
    for (const GrowthPoint& p : growth.points) {
        ns.push_back(double(p.n));
        ms.push_back(p.build_ms);
    }
    growth.fit = fit_power_law(ns, ms, options.fit_min_size);
    return growth;
}

const BenchRow* CompareRow::find(std::string_view set, unsigned threads) const {
    for (const BenchRow& r : speed)
        if (r.set == set && r.threads == threads) return &r;
    return nullptr;
}

double CompareRow::build_ms() const { return speed.empty() ? 0.0 : speed.front().build_ms; }
size_t CompareRow::structure_bytes() const { return speed.empty() ? 0 : speed.front().structure_bytes; }
double CompareRow::structure_bytes_per_primitive() const {
    return primitives ? double(structure_bytes()) / double(primitives) : 0.0;
}
double CompareRow::sah_cost() const { return speed.empty() ? 0.0 : speed.front().sah_cost; }

}  // namespace thicket
