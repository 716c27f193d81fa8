#include "thicket/grid/resolution.h"

#include <algorithm>
#include <cmath>

#include "thicket/core/error.h"

namespace thicket {

namespace {

/// Extents relative to the longest one (in [0, 1]), or nullopt-like all zero when degenerate.
bool normalized_extent(Vec3 extent, double e[3]) {
    const double longest = std::max({double(extent.x), double(extent.y), double(extent.z)});
    if (!std::isfinite(longest) || !(longest > 0.0)) return false;
    for (int a = 0; a < 3; ++a) {
        e[a] = double(extent[a]) / longest;
        if (!(e[a] >= 0.0) || !std::isfinite(e[a])) return false;
    }
    return true;
}

}  // namespace

std::string GridResolution::str() const {
    return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
}

GridResolution density_resolution(Vec3 extent, double cells_wanted, uint32_t max_per_axis, uint64_t max_cells) {
    GridResolution r;
    double e[3];
    if (!normalized_extent(extent, e)) return r;
    const double target = std::max(1.0, cells_wanted);
    // Scale s with s^k * prod(e) = target over the k axes that get more than one cell; an axis too
    // thin for one cell leaves the budget to the others.
    bool active[3] = {e[0] > 0.0, e[1] > 0.0, e[2] > 0.0};
    double s = 1.0;
    for (int round = 0; round < 3; ++round) {
        double prod = 1.0;
        int k = 0;
        for (int a = 0; a < 3; ++a)
            if (active[a]) prod *= e[a], ++k;
        s = std::pow(target / prod, 1.0 / k);
        bool dropped = false;
        for (int a = 0; a < 3; ++a)
            if (active[a] && e[a] * s < 1.0 && k > 1) active[a] = false, dropped = true;
        if (!dropped) break;
    }
    const double cap = double(std::max<uint32_t>(1, max_per_axis));
    for (int a = 0; a < 3; ++a)
        r.n[a] = active[a] ? uint32_t(std::clamp(std::round(e[a] * s), 1.0, cap)) : 1u;
    // Too many cells in all: shrink every axis by the same factor until it fits.
    while (r.cells() > max_cells) {
        const double f = std::cbrt(double(max_cells) / double(r.cells()));
        for (uint32_t& n : r.n) n = std::max<uint32_t>(1, uint32_t(std::floor(n * f)));
        if (f >= 1.0) break;  // cannot happen; keeps the loop finite whatever the rounding
    }
    return r;
}

GridResolution longest_axis_resolution(Vec3 extent, uint32_t cells_longest, const std::string& what) {
    GridResolution r;
    double e[3];
    if (!normalized_extent(extent, e)) return r;
    for (int a = 0; a < 3; ++a)
        r.n[a] = uint32_t(std::clamp(std::round(e[a] * cells_longest), 1.0, double(std::max<uint32_t>(1, cells_longest))));
    if (r.cells() > kMaxGridCells)
        throw Error(what + " gives " + r.str() + " = " + std::to_string(r.cells()) + " cells, more than the limit of " +
                    std::to_string(kMaxGridCells) + " (2^26); choose a smaller res, or res=0 for the automatic rule");
    return r;
}

}  // namespace thicket
