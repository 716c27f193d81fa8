#pragma once
// A kernel-independent reference for shape tests: the roots of an implicit (or signed-distance)
// function along a ray, by dense sampling in double and bisection of every sign change. Slow and
// simple on purpose; usable by any kernel whose surface is {p : f(p) = 0}.
#include <functional>
#include <optional>
#include <vector>

#include "thicket/core/ray.h"
#include "thicket/prims/shape_util.h"

namespace thicket::testing {

using Implicit = std::function<double(const Vec3d&)>;

/// Every sign change of f(org + t dir) over `samples` equal steps of [t0, t1], each refined by
/// bisection to double precision, ascending. A root closer to its neighbour than the step can be
/// missed: grazing rays need enough samples (or a test that checks the kernel's extra roots).
std::vector<double> roots_by_sampling(const Implicit& f, Vec3d org, Vec3d dir, double t0, double t1, size_t samples);

/// The ray's parameter interval through `box` (in double, widened by `pad` on every side), or
/// nullopt if it misses. Used to bound the sampling to where the surface can be.
std::optional<std::pair<double, double>> ray_box_interval(Vec3d org, Vec3d dir, const Aabb& box, double pad);

/// The first root t >= ray.tmin and <= ray.tmax of f along the ray inside `bounds`, or nullopt.
std::optional<double> first_root(const Implicit& f, const Ray& ray, const Aabb& bounds, size_t samples);

/// Signed distance to the torus (center, unit axis, R, r): sqrt((rho - R)^2 + y^2) - r.
double torus_distance(const Vec3d& p, const Vec3d& center, const Vec3d& axis, double R, double r);

}  // namespace thicket::testing
