#include "support/root_reference.h"

#include <algorithm>
#include <cmath>

namespace thicket::testing {

std::vector<double> roots_by_sampling(const Implicit& f, Vec3d org, Vec3d dir, double t0, double t1, size_t samples) {
    std::vector<double> roots;
    if (!(t1 >= t0) || samples < 1) return roots;
    auto at = [&](double t) { return f(org + dir * t); };
    double prev_t = t0, prev_f = at(t0);
    if (prev_f == 0.0) roots.push_back(t0);
    for (size_t i = 1; i <= samples; ++i) {
        const double t = t0 + (t1 - t0) * double(i) / double(samples);
        const double ft = at(t);
        if (ft == 0.0) {
            roots.push_back(t);
        } else if (prev_f != 0.0 && (ft < 0.0) != (prev_f < 0.0)) {
            double lo = prev_t, hi = t, flo = prev_f;
            for (int k = 0; k < 200 && hi - lo > 0.0; ++k) {
                const double mid = 0.5 * (lo + hi);
                if (mid <= lo || mid >= hi) break;
                const double fm = at(mid);
                if (fm == 0.0) {
                    lo = hi = mid;
                    break;
                }
                if ((fm < 0.0) == (flo < 0.0)) {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            roots.push_back(0.5 * (lo + hi));
        }
        prev_t = t;
        prev_f = ft;
    }
    return roots;
}

std::optional<std::pair<double, double>> ray_box_interval(Vec3d org, Vec3d dir, const Aabb& box, double pad) {
    double t0 = -INFINITY, t1 = INFINITY;
    for (int a = 0; a < 3; ++a) {
        const double lo = double(box.min[a]) - pad, hi = double(box.max[a]) + pad;
        if (dir[a] == 0.0) {
            if (org[a] < lo || org[a] > hi) return std::nullopt;
            continue;
        }
        double n = (lo - org[a]) / dir[a], x = (hi - org[a]) / dir[a];
        if (n > x) std::swap(n, x);
        t0 = std::max(t0, n);
        t1 = std::min(t1, x);
    }
    if (!(t0 <= t1)) return std::nullopt;
    return std::make_pair(t0, t1);
}

std::optional<double> first_root(const Implicit& f, const Ray& ray, const Aabb& bounds, size_t samples) {
    const Vec3d o(ray.org), d(ray.dir);
    const double pad = 1e-3 * max_component(bounds.extent());
    const auto span = ray_box_interval(o, d, bounds, pad);
    if (!span) return std::nullopt;
    const double t0 = std::max(span->first, double(ray.tmin)), t1 = std::min(span->second, double(ray.tmax));
    if (!(t0 <= t1)) return std::nullopt;
    for (double t : roots_by_sampling(f, o, d, t0, t1, samples))
        if (float(t) >= ray.tmin && float(t) <= ray.tmax) return t;
    return std::nullopt;
}

double torus_distance(const Vec3d& p, const Vec3d& center, const Vec3d& axis, double R, double r) {
    const Vec3d q = p - center;
    const double y = dot(q, axis);
    const double rho = length(q - axis * y);
    return std::hypot(rho - R, y) - r;
}

}  // namespace thicket::testing
