// Distance-estimated fractals (prims/fractal.h): sphere tracing against a dense march of the same
// estimator in double, the exact sphere of the Julia set of c = 0, the bounding sphere against
// samples of the set, the estimator's conservativeness, normals, windows and parameter errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/core/ray_box.h"
#include "thicket/prims/fractal.h"

namespace thicket::fractal_test {
namespace {

using D3 = std::array<double, 3>;

double norm(const D3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
Vec3 to_float(const D3& v) { return Vec3(float(v[0]), float(v[1]), float(v[2])); }
D3 at(const FractalSegment& s, double t) { return {s.o[0] + t * s.d[0], s.o[1] + t * s.d[1], s.o[2] + t * s.d[2]}; }

/// The eps-region along the segment by dense sampling (step h in object units): the first
/// sample with DE < eps, refined by bisection against the sample before it; and where the
/// region ends again (its thickness along the ray, for classifying a sliver).
struct DenseMarch {
    std::optional<double> t;  ///< first crossing
    double exit = 0.0;        ///< first sample after t with DE >= eps again (or t1)
};
template <class K>
DenseMarch dense_march(const K& k, const FractalSegment& s, double h) {
    const double eps = k.params().march.epsilon;
    const double dt = h / norm(s.d);
    DenseMarch r;
    double prev = s.t0;
    if (k.distance(at(s, s.t0)) < eps) {
        r.t = s.t0;
    } else {
        for (long i = 1;; ++i) {
            const double t = std::min(s.t0 + double(i) * dt, s.t1);
            if (k.distance(at(s, t)) < eps) {
                double lo = prev, hi = t;
                for (int j = 0; j < 100; ++j) {
                    const double m = 0.5 * (lo + hi);
                    if (!(m > lo && m < hi)) break;
                    (k.distance(at(s, m)) < eps ? hi : lo) = m;
                }
                r.t = hi;
                break;
            }
            if (t >= s.t1) return r;
            prev = t;
        }
    }
    r.exit = s.t1;
    for (long i = 1;; ++i) {
        const double t = *r.t + double(i) * dt;
        if (t >= s.t1) break;
        if (k.distance(at(s, t)) >= eps) {
            r.exit = t;
            break;
        }
    }
    return r;
}

/// Whether DE < eps within float rounding of t: the march's t is exact in double, but DE jumps
/// where the escape iteration count changes, so the float t may round to the other side.
template <class K>
bool in_region_near(const K& k, const FractalSegment& s, float t) {
    const double ulp = std::ldexp(std::fabs(double(t)), -23) + 1e-30;
    for (int i = -2; i <= 2; ++i)
        if (k.distance(at(s, double(t) + i * ulp)) < k.params().march.epsilon) return true;
    return false;
}

/// Rays from outside the bounding sphere aimed inside it, and rays starting inside it, with
/// direction lengths that vary (t is in units of the direction's length).
template <class K, class F>
void for_each_ray(const K& k, uint64_t seed, int n, F check) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> nd;
    std::uniform_real_distribution<double> u(-1.0, 1.0), len(0.3, 2.0);
    const FractalMarch& m = k.params().march;
    const double R = k.bounding_radius();
    auto world = [&](const D3& q) {
        return D3{m.center.x + m.scale * q[0], m.center.y + m.scale * q[1], m.center.z + m.scale * q[2]};
    };
    for (int i = 0; i < n; ++i) {
        D3 org, tgt{u(rng) * R, u(rng) * R, u(rng) * R};
        if (i % 5 == 4) {
            org = {u(rng) * 0.6 * R, u(rng) * 0.6 * R, u(rng) * 0.6 * R};
            tgt = {nd(rng), nd(rng), nd(rng)};
        } else {
            D3 v{nd(rng), nd(rng), nd(rng)};
            const double l = norm(v);
            for (int a = 0; a < 3; ++a) org[a] = 2.5 * R * v[a] / l;
        }
        D3 dir = i % 5 == 4 ? tgt : D3{tgt[0] - org[0], tgt[1] - org[1], tgt[2] - org[2]};
        const double s = len(rng) * m.scale / norm(dir);
        const Ray ray{to_float(world(org)), 0.0f, to_float({dir[0] * s, dir[1] * s, dir[2] * s}), kInfinity};
        check(ray);
    }
}

/// Sphere tracing agrees with the dense march: the same hits and misses and the same t within
/// eps, except where the march stepped over a sliver of the eps-region (thinner than a few eps
/// along the ray), which only a few rays may do. Every hit is a point of the eps-region.
template <class K>
void check_against_dense_march(const K& k, uint64_t seed, int n) {
    const double eps = k.params().march.epsilon;
    int hits = 0, misses = 0, slivers = 0, inside_starts = 0;
    for_each_ray(k, seed, n, [&](const Ray& ray) {
        ShapeHit h;
        const bool hit = k.intersect(ray, ray.tmax, h);
        FractalSegment s;
        if (!k.object_segment(ray, ray.tmax, s)) {
            ASSERT_FALSE(hit);
            ++misses;
            return;
        }
        const DenseMarch ref = dense_march(k, s, eps / 8.0);
        const double dlen = norm(s.d);
        if (hit) {
            ASSERT_GE(h.t, ray.tmin);
            ASSERT_LE(h.t, ray.tmax);
            ASSERT_TRUE(hit_within_bounds(ray, h.t, k.bounds()));
            EXPECT_TRUE(in_region_near(k, s, h.t)) << "a hit is a point where DE < eps";
            inside_starts += h.t == s.t0;
        }
        const bool agree = hit == ref.t.has_value() && (!hit || std::fabs(h.t - *ref.t) * dlen <= eps);
        if (agree) {
            (hit ? hits : misses) += 1;
            return;
        }
        // A disagreement must be a sliver: the region the reference entered first is at most
        // 4 eps thick along the ray, and sphere tracing's last step before it can overshoot that.
        ++slivers;
        ASSERT_TRUE(ref.t.has_value()) << "the march hit where the dense reference saw no eps-region";
        EXPECT_LE((ref.exit - *ref.t) * dlen, 4.0 * eps) << "stepped over a thick part of the region";
        if (hit) {
            EXPECT_GT(h.t, *ref.t) << "a hit before the reference's first crossing";
        }
    });
    std::printf("    %d hits, %d misses agree; %d slivers stepped over; %d hits at the segment start\n", hits, misses,
                slivers, inside_starts);
    EXPECT_GT(hits, n / 4);
    EXPECT_GT(misses, n / 20);
    EXPECT_LE(slivers, n / 50);
}

FractalMarch placed_march(int iterations, double eps) {
    FractalMarch m;
    m.center = Vec3(1.0f, -2.0f, 0.5f);
    m.scale = 2.5f;
    m.iterations = iterations;
    m.epsilon = eps;
    return m;
}

TEST(FractalJulia, SphereTracingMatchesDenseMarch) {
    Julia::Params p;
    p.march = placed_march(12, 2e-3);
    check_against_dense_march(Julia(p), 1, 400);
}

TEST(FractalJulia, SphereTracingMatchesDenseMarchOnAnotherSlice) {
    Julia::Params p;
    p.c = {-0.125, -0.256, 0.847, 0.0895};
    p.w = 0.3;
    p.march = placed_march(10, 1e-3);
    check_against_dense_march(Julia(p), 2, 300);
}

TEST(FractalMandelbulb, SphereTracingMatchesDenseMarch) {
    Mandelbulb::Params p;
    p.march = placed_march(8, 2e-3);
    check_against_dense_march(Mandelbulb(p), 3, 150);
}

TEST(FractalMandelbulb, PowerThreeMatchesDenseMarch) {
    Mandelbulb::Params p;
    p.power = 3.0;
    p.march = placed_march(10, 2e-3);
    check_against_dense_march(Mandelbulb(p), 4, 150);
}

TEST(FractalJulia, ConstantZeroIsAnExactSphere) {
    // For c = 0, z_n = z^(2^n): DE = 0.5 r ln r exactly at every escape iteration, so the
    // eps-isosurface is the sphere 0.5 r ln r = eps (points nearer 1 do not escape: DE = 0).
    Julia::Params p;
    p.c = {0, 0, 0, 0};
    p.march.epsilon = 1e-3;
    p.march.iterations = 14;
    p.march.center = Vec3(0.25f, 0.5f, -0.75f);
    p.march.scale = 2.0f;
    const Julia j(p);
    double r = 1.0 + 2.0 * p.march.epsilon;
    for (int i = 0; i < 50; ++i) r -= (0.5 * r * std::log(r) - p.march.epsilon) / (0.5 * (std::log(r) + 1.0));
    const double wr = r * p.march.scale;
    const D3 wc{0.25, 0.5, -0.75};
    std::mt19937_64 rng(5);
    std::normal_distribution<double> nd;
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int hits = 0, misses = 0;
    for (int i = 0; i < 2000; ++i) {
        D3 org{nd(rng), nd(rng), nd(rng)};
        const double l = norm(org);
        for (int a = 0; a < 3; ++a) org[a] = wc[a] + 3.0 * wr * org[a] / l;
        const double off = u(rng) * 1.2;  // aim at an offset from the center, up to beyond the sphere
        D3 side{nd(rng), nd(rng), nd(rng)}, back{wc[0] - org[0], wc[1] - org[1], wc[2] - org[2]};
        const double bs = (side[0] * back[0] + side[1] * back[1] + side[2] * back[2]) / (norm(back) * norm(back));
        for (int a = 0; a < 3; ++a) side[a] -= bs * back[a];
        const double sl = norm(side);
        D3 dir;
        for (int a = 0; a < 3; ++a) dir[a] = back[a] + off * wr * side[a] / sl;
        const Ray ray{to_float(org), 0.0f, to_float(dir), kInfinity};
        D3 o2, d2;
        for (int a = 0; a < 3; ++a) o2[a] = double(ray.org[a]) - wc[a], d2[a] = ray.dir[a];
        const double A = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2];
        const double B = o2[0] * d2[0] + o2[1] * d2[1] + o2[2] * d2[2];
        const double C = o2[0] * o2[0] + o2[1] * o2[1] + o2[2] * o2[2];
        const double closest = std::sqrt(std::max(0.0, C - B * B / A));
        ShapeHit h;
        const bool hit = j.intersect(ray, ray.tmax, h);
        if (closest > wr) {
            EXPECT_FALSE(hit) << "passes " << (closest - wr) / wr << " radii outside";
            ++misses;
        } else if (closest < wr * (1.0 - 1e-4)) {
            ASSERT_TRUE(hit) << "passes " << (wr - closest) / wr << " radii inside";
            const double te = (-B - std::sqrt(B * B - A * (C - wr * wr))) / A;
            EXPECT_NEAR(h.t, te, 1e-6 * te);
            ++hits;
        }
    }
    EXPECT_GT(hits, 800);
    EXPECT_GT(misses, 200);
}

// ---- bounds and the estimator --------------------------------------------------------------

/// Grid points of a cube 1.25 times the bounding sphere: every point of the eps-region (DE < eps)
/// lies inside the bounding sphere, every non-escaping point inside the proven set radius, and
/// DE > eps on the bounding sphere itself.
template <class K>
void check_bounding_sphere(const K& k) {
    const double eps = k.params().march.epsilon, R = k.bounding_radius();
    const int n = 64;
    int region = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int l = 0; l < n; ++l) {
                const D3 p{R * 1.25 * (-1.0 + 2.0 * (i + 0.5) / n), R * 1.25 * (-1.0 + 2.0 * (j + 0.5) / n),
                           R * 1.25 * (-1.0 + 2.0 * (l + 0.5) / n)};
                const double de = k.distance(p);
                if (de >= eps) continue;
                ++region;
                ASSERT_LE(norm(p), R);
                if (de == 0.0) {
                    ASSERT_LE(norm(p), k.set_radius());
                }
            }
    EXPECT_GT(region, 100) << "the grid must sample the set";
    std::mt19937_64 rng(6);
    std::normal_distribution<double> nd;
    for (int i = 0; i < 20000; ++i) {
        D3 v{nd(rng), nd(rng), nd(rng)};
        const double l = norm(v);
        for (double& x : v) x *= R / l;
        ASSERT_GT(k.distance(v), eps) << "the eps-region reaches the bounding sphere";
    }
    // The world box encloses the placed sphere.
    const FractalMarch& m = k.params().march;
    for (int a = 0; a < 3; ++a) {
        EXPECT_LE(double(k.bounds().min[a]), m.center[a] - m.scale * R);
        EXPECT_GE(double(k.bounds().max[a]), m.center[a] + m.scale * R);
    }
}

TEST(FractalBounds, JuliaBoundingSphereHoldsTheSet) {
    Julia::Params p;
    check_bounding_sphere(Julia(p));
    p.c = {-1.0, 0.2, 0.0, 0.0};  // a set reaching close to its radius bound
    p.march.epsilon = 1e-2;
    check_bounding_sphere(Julia(p));
    p.w = 0.5;
    check_bounding_sphere(Julia(p));
}

TEST(FractalBounds, MandelbulbBoundingSphereHoldsTheSet) {
    Mandelbulb::Params p;
    const Mandelbulb m8(p);
    EXPECT_NEAR(m8.set_radius(), std::pow(2.0, 1.0 / 7.0), 1e-15);
    check_bounding_sphere(m8);
    p.power = 2.0;
    check_bounding_sphere(Mandelbulb(p));
    p.power = 5.5;
    p.march.epsilon = 1e-2;
    check_bounding_sphere(Mandelbulb(p));
}

/// DE never exceeds the distance to a sampled point of the set (a non-escaping grid point):
/// it is a lower bound of the distance, which is what makes a sphere-tracing step safe.
template <class K>
void check_conservative(const K& k, uint64_t seed) {
    const double R = k.bounding_radius();
    const int n = 56;
    std::vector<D3> set;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int l = 0; l < n; ++l) {
                const D3 p{R * (-1.0 + 2.0 * (i + 0.5) / n), R * (-1.0 + 2.0 * (j + 0.5) / n),
                           R * (-1.0 + 2.0 * (l + 0.5) / n)};
                if (k.distance(p) == 0.0) set.push_back(p);
            }
    ASSERT_GT(set.size(), 500u);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int tested = 0;
    for (int q = 0; q < 400; ++q) {
        const D3 p{u(rng) * R, u(rng) * R, u(rng) * R};
        const double de = k.distance(p);
        if (de == 0.0) continue;
        double nearest = HUGE_VAL;
        for (const D3& s : set) nearest = std::min(nearest, std::hypot(p[0] - s[0], p[1] - s[1], p[2] - s[2]));
        ++tested;
        EXPECT_LE(de, nearest);
    }
    EXPECT_GT(tested, 200);
}

TEST(FractalBounds, EstimatorsAreConservative) {
    check_conservative(Julia(Julia::Params{}), 7);
    check_conservative(Mandelbulb(Mandelbulb::Params{}), 8);
}

// ---- normals, windows, hashing, errors -----------------------------------------------------

template <class K>
void check_normals(const K& k, uint64_t seed) {
    int hits = 0, facing = 0;
    for_each_ray(k, seed, 300, [&](const Ray& ray) {
        ShapeHit h;
        if (!k.intersect(ray, ray.tmax, h)) return;
        const Vec3 n = k.normal(ray.org + ray.dir * h.t, h.u, h.v);
        ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
        EXPECT_NEAR(length(n), 1.0f, 1e-5f);
        ++hits;
        facing += dot(n, ray.dir) < 0.0f;
    });
    // DE grows away from the set, so its gradient faces the rays that come in from outside.
    EXPECT_GT(facing, hits * 3 / 4);
    // Inside the set (DE = 0 all around) and at its center the normal still is a unit vector.
    const FractalMarch& m = k.params().march;
    for (const Vec3& p : {m.center, m.center + Vec3(0.01f, 0.0f, 0.0f) * m.scale}) {
        const Vec3 n = k.normal(p, 0.0f, 0.0f);
        ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
        EXPECT_NEAR(length(n), 1.0f, 1e-6f);
    }
}

TEST(FractalNormals, FiniteUnitAndFacingTheRay) {
    Julia::Params jp;
    jp.march = placed_march(12, 1e-3);
    check_normals(Julia(jp), 9);
    Mandelbulb::Params mp;
    mp.march = placed_march(8, 1e-3);
    check_normals(Mandelbulb(mp), 10);
}

TEST(FractalKernel, RespectsTheRayWindowAndStartsInside) {
    Mandelbulb::Params p;
    p.march.epsilon = 2e-3;
    const Mandelbulb m(p);
    int hits = 0;
    for_each_ray(m, 11, 200, [&](const Ray& ray) {
        ShapeHit first;
        if (!m.intersect(ray, ray.tmax, first)) return;
        ++hits;
        ShapeHit h;
        const float before = first.t * (1.0f - 1e-3f);
        if (first.t > ray.tmin && m.intersect(ray, before, h)) {
            EXPECT_LE(h.t, before);
        }
        // A ray starting at a point of the eps-region is blocked at once.
        Ray inside = ray;
        inside.tmin = first.t;
        FractalSegment s;
        ASSERT_TRUE(m.object_segment(inside, inside.tmax, s));
        if (m.distance(at(s, s.t0)) < p.march.epsilon) {
            ASSERT_TRUE(m.intersect(inside, inside.tmax, h));
            EXPECT_EQ(h.t, inside.tmin);
        }
    });
    EXPECT_GT(hits, 100);
    // The center of the bulb is in the set: a ray from there hits at tmin.
    ShapeHit h;
    ASSERT_TRUE(m.intersect({Vec3(0.0f), 0.5f, Vec3(1, 0, 0), kInfinity}, kInfinity, h));
    EXPECT_EQ(h.t, 0.5f);
}

TEST(FractalKernel, HashesDistinguishParameters) {
    Julia::Params a, b;
    b.c[2] += 0.01;
    EXPECT_EQ(Julia(a).hash(1), Julia(a).hash(1));
    EXPECT_NE(Julia(a).hash(1), Julia(b).hash(1));
    b = a;
    b.march.iterations += 1;
    EXPECT_NE(Julia(a).hash(1), Julia(b).hash(1));
    Mandelbulb::Params m, n;
    n.power = 7.0;
    EXPECT_NE(Mandelbulb(m).hash(1), Mandelbulb(n).hash(1));
    n = m;
    n.march.scale = 2.0f;
    EXPECT_NE(Mandelbulb(m).hash(1), Mandelbulb(n).hash(1));
}

TEST(FractalKernel, BadParametersAreErrors) {
    auto julia_throws = [](auto edit) {
        Julia::Params p;
        edit(p);
        EXPECT_THROW(Julia{p}, Error);
    };
    julia_throws([](Julia::Params& p) { p.march.iterations = 0; });
    julia_throws([](Julia::Params& p) { p.march.iterations = 100000; });
    julia_throws([](Julia::Params& p) { p.march.epsilon = 0.0; });
    julia_throws([](Julia::Params& p) { p.march.epsilon = NAN; });
    julia_throws([](Julia::Params& p) { p.march.step_factor = 0.0; });
    julia_throws([](Julia::Params& p) { p.march.step_factor = 1.5; });
    julia_throws([](Julia::Params& p) { p.march.max_steps = 0; });
    // Issue 16: each limit alone let one ray cost 1000 x 2^24 map iterations (minutes).
    julia_throws([](Julia::Params& p) {
        p.march.iterations = 1000;
        p.march.max_steps = 1 << 24;
        p.march.epsilon = 1e-30;
    });
    julia_throws([](Julia::Params& p) {
        p.march.iterations = 257;
        p.march.max_steps = 1 << 14;  // 257 x 16384 = 4,210,688 > 2^22
    });
    {
        Julia::Params p;
        p.march.iterations = 256;
        p.march.max_steps = 1 << 14;  // exactly 2^22: allowed
        EXPECT_NO_THROW(Julia{p});
        Mandelbulb::Params m;
        m.march.iterations = 1000;
        m.march.max_steps = 1 << 24;
        EXPECT_THROW(Mandelbulb{m}, Error);
    }
    julia_throws([](Julia::Params& p) { p.march.scale = -1.0f; });
    julia_throws([](Julia::Params& p) { p.march.center.x = INFINITY; });
    julia_throws([](Julia::Params& p) { p.c[1] = NAN; });
    julia_throws([](Julia::Params& p) { p.bailout = 1.0; });
    julia_throws([](Julia::Params& p) { p.w = 5.0; });
    auto bulb_throws = [](auto edit) {
        Mandelbulb::Params p;
        edit(p);
        EXPECT_THROW(Mandelbulb{p}, Error);
    };
    bulb_throws([](Mandelbulb::Params& p) { p.power = 1.5; });
    bulb_throws([](Mandelbulb::Params& p) { p.power = 40.0; });
    bulb_throws([](Mandelbulb::Params& p) { p.power = NAN; });
    bulb_throws([](Mandelbulb::Params& p) { p.bailout = 1.0; });
    bulb_throws([](Mandelbulb::Params& p) { p.march.iterations = -3; });
    try {
        Julia::Params p;
        p.w = 5.0;
        Julia j(p);
        FAIL() << "accepted a slice that misses the set";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("w = 5"), std::string::npos) << e.what();
    }
}

TEST(FractalKernel, DegenerateRaysMiss) {
    const Julia j(Julia::Params{});
    ShapeHit h;
    EXPECT_FALSE(j.intersect({Vec3(0.0f, 0.0f, 3.0f), 0.0f, Vec3(0.0f), kInfinity}, kInfinity, h));
    EXPECT_FALSE(j.intersect({Vec3(NAN, 0.0f, 3.0f), 0.0f, Vec3(0, 0, -1), kInfinity}, kInfinity, h));
    EXPECT_FALSE(j.intersect({Vec3(0.0f, 0.0f, 3.0f), 2.0f, Vec3(0, 0, -1), 1.0f}, 1.0f, h));
    EXPECT_FALSE(j.intersect({Vec3(0.0f, 0.0f, 3.0f), 0.0f, Vec3(0, 0, 1), kInfinity}, kInfinity, h))
        << "pointing away";
}

}  // namespace
}  // namespace thicket::fractal_test
