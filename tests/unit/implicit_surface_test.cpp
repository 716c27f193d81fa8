// Implicit surfaces (prims/implicit.h) as functions: gradients, interval extensions, bounds,
// Lipschitz bounds, normals (double points included), hashing and parameter errors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "implicit_reference.h"
#include "thicket/core/error.h"
#include "thicket/prims/implicit.h"

namespace thicket::implicit_surface_test {
namespace {

using namespace implicit_reference;

TEST(ImplicitKernel, LipschitzBoundHoldsOverTheBox) {
    auto check = [](const auto& k) {
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        const Box3d box = object_box(k);
        double worst = 0.0;
        for (int i = 0; i < 20000; ++i) {
            Vec3d p;
            for (int a = 0; a < 3; ++a) p[a] = box.lo[a] + u(rng) * (box.hi[a] - box.lo[a]);
            worst = std::max(worst, norm(grad_at(k.surface(), p)));
        }
        EXPECT_LE(worst, k.lipschitz());
        EXPECT_GT(worst, 0.1 * k.lipschitz()) << "the bound should not be absurdly loose";
    };
    check(ImplicitKernel<TangleCube>(TangleCube{}));
    check(ImplicitKernel<BarthSextic>(BarthSextic{1.0}));
    check(ImplicitKernel<BlobSum>(four_blobs()));
}

TEST(ImplicitKernel, NormalsAreUnitOutwardGradients) {
    auto check = [](const auto& k) {
        std::mt19937_64 rng(11);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        const Box3d box = object_box(k);
        int n = 0;
        for (int i = 0; i < 3000 && n < 300; ++i) {
            Vec3d p;
            for (int a = 0; a < 3; ++a) p[a] = 0.5 * (box.lo[a] + box.hi[a]) + u(rng) * 0.5 * (box.hi[a] - box.lo[a]);
            const auto q = project_to_surface(k.surface(), p, box);
            if (!q) continue;
            ++n;
            const Vec3 nrm = k.normal(to_float(to_world(k.options(), *q)), 0.0f, 0.0f);
            ASSERT_TRUE(std::isfinite(nrm.x) && std::isfinite(nrm.y) && std::isfinite(nrm.z));
            EXPECT_NEAR(length(nrm), 1.0f, 1e-5f);
            // Outward: f increases along the normal (central differences, independent of gradient()).
            const double h = 1e-6;
            Vec3d fd;
            for (int a = 0; a < 3; ++a) {
                Vec3d pp = *q, pm = *q;
                pp[a] += h, pm[a] -= h;
                fd[a] = (f_at(k.surface(), pp) - f_at(k.surface(), pm)) / (2 * h);
            }
            const double fl = norm(fd);
            if (fl < 1e-3) continue;  // near a double point the direction is ill-defined
            const double cosang = (fd[0] * nrm.x + fd[1] * nrm.y + fd[2] * nrm.z) / fl;
            EXPECT_GT(cosang, 1.0 - 1e-4);
        }
        EXPECT_GT(n, 100);
    };
    check(ImplicitKernel<TangleCube>(TangleCube{}, placed()));
    check(ImplicitKernel<BarthSextic>(BarthSextic{1.0}, placed()));
    check(ImplicitKernel<BlobSum>(four_blobs(), placed()));
}

TEST(ImplicitKernel, NormalIsFiniteAtBarthDoublePoints) {
    // (+-1, 0, 0) and permutations are double points of Barth's sextic: f = 0 and grad f = 0.
    const ImplicitKernel<BarthSextic> k(BarthSextic{1.5});
    for (const Vec3d& p : {Vec3d{1, 0, 0}, Vec3d{0, -1, 0}, Vec3d{0, 0, 1}}) {
        EXPECT_EQ(f_at(k.surface(), p), 0.0);
        EXPECT_EQ(norm(grad_at(k.surface(), p)), 0.0);
        const Vec3 n = k.normal(to_float(p), 0.0f, 0.0f);
        ASSERT_TRUE(std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z));
        EXPECT_NEAR(length(n), 1.0f, 1e-6f);
    }
    const Vec3 c = k.normal(Vec3(0.0f), 0.0f, 0.0f);  // not on the surface, but must stay finite
    EXPECT_NEAR(length(c), 1.0f, 1e-6f);
}

TEST(ImplicitKernel, GradientsMatchFiniteDifferences) {
    auto check = [](const auto& s, const Box3d& box) {
        std::mt19937_64 rng(12);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        for (int i = 0; i < 500; ++i) {
            Vec3d p;
            for (int a = 0; a < 3; ++a) p[a] = box.lo[a] + u(rng) * (box.hi[a] - box.lo[a]);
            const Vec3d g = grad_at(s, p);
            for (int a = 0; a < 3; ++a) {
                const double h = 1e-5;
                Vec3d pp = p, pm = p;
                pp[a] += h, pm[a] -= h;
                const double fd = (f_at(s, pp) - f_at(s, pm)) / (2 * h);
                EXPECT_NEAR(g[a], fd, 1e-5 * (1.0 + std::fabs(fd))) << "axis " << a;
            }
        }
    };
    check(TangleCube{}, TangleCube{}.box());
    check(BarthSextic{1.0}, BarthSextic{1.0}.box());
    check(four_blobs(), four_blobs().box());
}

TEST(ImplicitKernel, IntervalExtensionsEncloseSampledValuesAndSlopes) {
    // Along random lines, over random t-intervals: the line evaluators' value and slope enclose
    // f and df/dt at sample points (df/dt by the gradient, which the previous test checks).
    auto check = [](const auto& s, auto make_eval) {
        std::mt19937_64 rng(13);
        std::uniform_real_distribution<double> u(-1.5, 1.5), w(0.0, 1.0);
        for (int i = 0; i < 2000; ++i) {
            const Line3d l{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}};
            const auto e = make_eval(s, l);
            const double t0 = u(rng), t1 = t0 + w(rng) * std::pow(10.0, -4.0 * w(rng));
            const Interval t(t0, t1);
            const Interval fv = e.value(t), sl = e.slope(t);
            for (int j = 0; j <= 8; ++j) {
                const double tj = t0 + (t1 - t0) * j / 8;
                const Vec3d p = l.at(tj);
                const double exact = f_at(s, p), slope = dotd(grad_at(s, p), l.d);
                const double fuzz = 1e-12 * (1.0 + std::fabs(exact));  // the point evaluation's own rounding
                ASSERT_GE(exact, fv.lo - fuzz);
                ASSERT_LE(exact, fv.hi + fuzz);
                ASSERT_GE(slope, sl.lo - 1e-12 * (1.0 + std::fabs(slope)));
                ASSERT_LE(slope, sl.hi + 1e-12 * (1.0 + std::fabs(slope)));
                ASSERT_NEAR(e.value(tj), exact, fuzz);
            }
        }
    };
    auto generic = [](const auto& s, const Line3d& l) { return GenericLineEval<std::decay_t<decltype(s)>>(s, l); };
    check(TangleCube{}, generic);
    check(BarthSextic{1.0}, generic);
    check(four_blobs(), generic);
    check(four_blobs(), [](const BlobSum& s, const Line3d& l) { return BlobsLineEval(s, l); });
    BlobSum many;  // more blobs than BlobsLineEval keeps inline
    many.threshold = 0.6;
    for (int i = 0; i < 12; ++i) many.blobs.push_back({{0.1 * i - 0.6, 0.05 * (i % 3), -0.04 * (i % 4)}, 1.0, 0.3});
    check(many, [](const BlobSum& s, const Line3d& l) { return BlobsLineEval(s, l); });
}

TEST(ImplicitKernel, TangleCubeBoundsContainTheSurface) {
    // Roots along random lines through a box twice the size: all must lie in box().
    const TangleCube s;
    const Box3d box = s.box();
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    std::normal_distribution<double> nd;
    for (int i = 0; i < 800; ++i) {
        Line3d l{{u(rng) * box.hi[0], u(rng) * box.hi[1], u(rng) * box.hi[2]}, {nd(rng), nd(rng), nd(rng)}};
        double t = -10.0;
        for (int r = 0; r < 8; ++r) {
            const auto root = reference_first_root(s, l, t, 10.0, 4096);
            if (!root) break;
            const Vec3d p = l.at(*root);
            for (int a = 0; a < 3; ++a) ASSERT_LE(std::fabs(p[a]), box.hi[a]);
            t = *root + 1e-6;
        }
    }
    // The bound is attained: at y = z = sqrt(2.5) the surface reaches x = box.hi - 1e-3.
    const double r = std::sqrt(2.5);
    EXPECT_NEAR(f_at(s, Vec3d{box.hi[0] - 1e-3, r, r}), 0.0, 1e-9);
}

TEST(ImplicitKernel, WorldBoundsEncloseThePlacedBox) {
    const ImplicitOptions o = placed();
    const ImplicitKernel<BlobSum> k(four_blobs(), o);
    const Box3d box = four_blobs().box();
    const Vec3d lo = to_world(o, box.lo), hi = to_world(o, box.hi);
    for (int a = 0; a < 3; ++a) {
        EXPECT_LE(double(k.bounds().min[a]), lo[a]);
        EXPECT_GE(double(k.bounds().max[a]), hi[a]);
        EXPECT_NEAR(k.bounds().min[a], lo[a], 1e-5);
    }
}

TEST(ImplicitKernel, ImplicitAndBlobsModelShapeKernelAndHash) {
    const Implicit tangle("tangle-cube", placed()), barth("barth-sextic", placed(), 1.2);
    // Through a corner lobe of the placed tangle (object x = y = 1.58, where the lobes are thickest).
    const Ray ray{Vec3(0.5f + 1.5f * 1.58f, -1.25f + 1.5f * 1.58f, 10.0f), 0.0f, Vec3(0.01f, 0.02f, -1.0f), kInfinity};
    ShapeHit h1, h2;
    ASSERT_TRUE(tangle.intersect(ray, ray.tmax, h1));
    ASSERT_TRUE(std::get<0>(tangle.kernel()).intersect(ray, ray.tmax, h2));
    EXPECT_EQ(h1.t, h2.t);
    EXPECT_NE(tangle.hash(1), barth.hash(1));
    EXPECT_EQ(tangle.hash(1), Implicit("tangle-cube", placed()).hash(1));
    EXPECT_NE(barth.hash(1), Implicit("barth-sextic", placed(), 1.3).hash(1));
    const Blobs blobs(four_blobs(), placed());
    BlobSum other = four_blobs();
    other.blobs[2].radius += 0.01;
    EXPECT_NE(blobs.hash(1), Blobs(other, placed()).hash(1));
    EXPECT_NE(blobs.hash(1), Blobs(four_blobs(), placed(ImplicitMethod::sphere_tracing)).hash(1));
}

TEST(ImplicitKernel, DegenerateRaysMiss) {
    const ImplicitKernel<TangleCube> k(TangleCube{});
    ShapeHit h;
    EXPECT_FALSE(k.intersect({Vec3(0.0f, 0.0f, 1.58f), 0.0f, Vec3(0.0f), kInfinity}, kInfinity, h));
    EXPECT_FALSE(k.intersect({Vec3(NAN, 0.0f, 5.0f), 0.0f, Vec3(0, 0, -1), kInfinity}, kInfinity, h));
    EXPECT_FALSE(k.intersect({Vec3(0.0f, 0.0f, 5.0f), 0.0f, Vec3(NAN, 0, -1), kInfinity}, kInfinity, h));
    EXPECT_FALSE(k.intersect({Vec3(0.0f, 0.0f, 5.0f), 3.0f, Vec3(0, 0, -1), 1.0f}, 1.0f, h)) << "tmin > tmax";
    // The z axis runs through the tangle's central hole: f(0, 0, z) = z^4 - 5z^2 + 11.8 > 0.
    EXPECT_FALSE(k.intersect({Vec3(0.0f, 0.0f, 5.0f), 0.0f, Vec3(0, 0, -1), kInfinity}, kInfinity, h));
    // At x = y = sqrt(2.5) the axis terms are minimal and the ray meets the box's extreme z.
    const float x = std::sqrt(2.5f);
    ASSERT_TRUE(k.intersect({Vec3(x, x, 5.0f), 0.0f, Vec3(0, 0, -1), kInfinity}, kInfinity, h));
    const double g = 2.0 * TangleCube::axis_term(double(x)) + TangleCube::kConstant;  // z^4 - 5z^2 + g = 0
    EXPECT_NEAR(h.t, 5.0 - std::sqrt((5.0 + std::sqrt(25.0 - 4.0 * g)) / 2.0), 1e-5);
}

TEST(ImplicitKernel, BadParametersAreErrors) {
    ImplicitOptions o;
    o.scale = 0.0f;
    EXPECT_THROW(ImplicitKernel<TangleCube>(TangleCube{}, o), Error);
    o = {};
    o.center.y = NAN;
    EXPECT_THROW(ImplicitKernel<TangleCube>(TangleCube{}, o), Error);
    o = {};
    o.epsilon = -1.0;
    EXPECT_THROW(ImplicitKernel<TangleCube>(TangleCube{}, o), Error);
    o = {};
    o.max_steps = 0;
    EXPECT_THROW(ImplicitKernel<TangleCube>(TangleCube{}, o), Error);
    EXPECT_THROW(ImplicitKernel<BarthSextic>(BarthSextic{0.0}), Error);
    EXPECT_THROW(ImplicitKernel<BarthSextic>(BarthSextic{INFINITY}), Error);
    EXPECT_THROW(Implicit("torus", {}), Error);
    EXPECT_THROW(parse_implicit_method("newton"), Error);
    EXPECT_EQ(parse_implicit_method("sphere-tracing"), ImplicitMethod::sphere_tracing);
    BlobSum s;
    EXPECT_THROW(Blobs(s, {}), Error) << "no blobs";
    s = four_blobs();
    s.threshold = 0.0;
    EXPECT_THROW(Blobs(s, {}), Error);
    s = four_blobs();
    s.blobs[1].radius = -1.0;
    EXPECT_THROW(Blobs(s, {}), Error);
    s = four_blobs();
    s.blobs[1].weight = 0.0;
    EXPECT_THROW(Blobs(s, {}), Error);
    s = four_blobs();
    s.blobs[0].center[2] = INFINITY;
    try {
        Blobs b(s, {});
        FAIL() << "accepted an infinite center";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("blob 0"), std::string::npos) << e.what();
    }
}

// Each sphere-tracing step sums every blob the ray passes near, so the steps and the blobs bound
// the work per ray only together; the interval method's span budget shrinks with the blobs.
TEST(ImplicitKernel, WorkPerRayIsBoundedByStepsTimesBlobs) {
    BlobSum many;
    for (size_t i = 0; i < 1024; ++i) many.blobs.push_back({{0.01 * double(i), 0.0, 0.0}, 1.0, 1.0});
    ImplicitOptions o;
    o.method = ImplicitMethod::sphere_tracing;
    o.max_steps = int(kMaxImplicitWorkPerRay / 1024);
    EXPECT_NO_THROW(Blobs(many, o)) << "exactly at the bound";
    o.max_steps += 1;
    try {
        Blobs b(many, o);
        FAIL() << "accepted max_steps x blobs above kMaxImplicitWorkPerRay";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("x 1024"), std::string::npos) << e.what();
    }
    o.method = ImplicitMethod::interval;  // max_steps is unused there: its budget adapts instead
    const Blobs interval(many, o);
    ShapeHit hit{};
    const Ray ray{{5.0f, 0.0f, 10.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, kInfinity};
    EXPECT_TRUE(interval.intersect(ray, kInfinity, hit)) << "the blobs' union covers x = 5 on the axis";

    BlobSum too_many;
    too_many.blobs.assign(kMaxBlobs + 1, Blob{{0.0, 0.0, 0.0}, 1.0, 1.0});
    try {
        Blobs b(too_many, {});
        FAIL() << "accepted more than kMaxBlobs blobs";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxBlobs + 1)), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace thicket::implicit_surface_test
