#pragma once
/// What the tests that check against independent truth share: the sample scale of
/// sanitizer builds, and double-precision vectors that share no arithmetic with the library's
/// float Vec3 (the expected values must not inherit the code under test's rounding), and a slab
/// test in double.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

namespace thicket::testing {

// g++ says "sanitized" by __SANITIZE_ADDRESS__; clang 14 (the CI sanitizer job's compiler) does
// not define it, only THICKET_SANITIZED (CMakeLists.txt) and __has_feature: before that was
// checked, the job ran these tests at the full sample counts.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__) || defined(THICKET_SANITIZED)
inline constexpr uint32_t kWorkScale = 4;  ///< sanitizer builds: a quarter of the samples, same bounds in SE
#else
inline constexpr uint32_t kWorkScale = 1;
#endif

inline constexpr double kPiD = 3.14159265358979323846;

/// A double-precision point, direction or colour.
struct D3 {
    double x = 0, y = 0, z = 0;
    D3 operator+(D3 b) const { return {x + b.x, y + b.y, z + b.z}; }
    D3 operator-(D3 b) const { return {x - b.x, y - b.y, z - b.z}; }
    D3 operator*(double s) const { return {x * s, y * s, z * s}; }
    D3 operator*(D3 b) const { return {x * b.x, y * b.y, z * b.z}; }  ///< component-wise (colours)
};
inline double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double norm(D3 a) { return std::sqrt(dot(a, a)); }
inline D3 unit(D3 a) { return a * (1.0 / norm(a)); }

/// The ray's interval inside `box` by the slab test in double, from r.tmin: {t_in, t_out}, with
/// t_in > t_out when it misses. Independent of the library's float slab tests (and their FMA forms).
inline std::pair<double, double> slab_double(const Ray& r, const Aabb& box) {
    double t_in = r.tmin, t_out = INFINITY;
    for (int a = 0; a < 3; ++a) {
        const double o = r.org[a], d = r.dir[a];
        if (d == 0.0) {
            if (o < box.min[a] || o > box.max[a]) return {1.0, 0.0};
            continue;
        }
        double t0 = (double(box.min[a]) - o) / d, t1 = (double(box.max[a]) - o) / d;
        if (t0 > t1) std::swap(t0, t1);
        t_in = std::max(t_in, t0);
        t_out = std::min(t_out, t1);
    }
    return {t_in, t_out};
}

}  // namespace thicket::testing
