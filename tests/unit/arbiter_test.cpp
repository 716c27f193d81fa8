// The bench's rounding arbiter (bench/arbiter.h) settles only what float rounding can explain: a
// ray within rounding of the mesh's boundary, a distance off by a few ulps. A dropped hit inside
// a triangle or in the crack between two, an invented one, a far-off t, a hit outside the ray's
// interval, a hit the reference missed, a wrong any-hit answer or a hit on the wrong triangle of
// an instance (its transform ignored) stay disagreements. Every figure below is worked by hand
// from the triangle's coordinates, not by the arbiter's own arithmetic.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "thicket/bench/agreement.h"
#include "thicket/bench/arbiter.h"
#include "thicket/prims/shapes.h"
#include "thicket/scene/scene.h"

namespace arbiter_test {

using namespace thicket;

/// Triangle 0: (0,0,0), (1,0,0), (0,1,0) in the plane z = 0; triangle 1 the same at z = -1.
Scene two_triangles() {
    Scene s;
    s.name = "two-triangles";
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}, {1, 0, -1}, {0, 1, -1}};
    m.indices = {0, 1, 2, 3, 4, 5};
    s.add_mesh(m);
    return s;
}

/// A ray straight down (-z) from height 1 through (x, y).
Ray down(float x, float y) { return Ray{{x, y, 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, INFINITY}; }

TEST(Arbiter, ExactVerdictsOfOneTriangle) {
    const Scene s = two_triangles();
    const RoundingArbiter arbiter(s);
    // Through (0.25, 0.25): the plane at t = 1, 0.25 from the nearest edges (x = 0, y = 0), and
    // delta(1) = 8 * 2^-24 * (1 + 1 * 1).
    const RoundingArbiter::Verdict v = arbiter.judge(down(0.25f, 0.25f), 0, 1.0);
    ASSERT_TRUE(v.triangle);
    EXPECT_DOUBLE_EQ(v.t, 1.0);
    EXPECT_NEAR(v.depth, 0.25, 1e-12);
    EXPECT_NEAR(v.point_distance, 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(v.delta, 8.0 * 0x1p-24 * 2.0);
    // Outside, past the hypotenuse x + y = 1 by 0.1 * sqrt(2) / 2 ... measured sideways.
    EXPECT_NEAR(arbiter.judge(down(0.6f, 0.5f), 0, 1.0).depth, -0.1 / std::sqrt(2.0), 1e-7);
    // The point at t = 1.5 lies 0.5 below the plane.
    EXPECT_NEAR(arbiter.judge(down(0.25f, 0.25f), 0, 1.5).point_distance, 0.5, 1e-12);
    EXPECT_FALSE(arbiter.judge(down(0.25f, 0.25f), 7, 1.0).triangle) << "no such primitive";
}

TEST(Arbiter, DroppedOrInventedHitsStayDisagreements) {
    const Scene s = two_triangles();
    const RoundingArbiter arbiter(s);
    const Ray centre = down(0.25f, 0.25f);
    const Hit right{1.0f, 0.25f, 0.25f, 0};
    EXPECT_TRUE(arbiter.certain(centre, 0));
    EXPECT_TRUE(arbiter.possible(centre, right));
    // The reference hits the triangle's middle; a candidate that misses, or reports the one
    // behind it, is wrong.
    EXPECT_FALSE(arbiter.candidate_within_rounding(centre, right, Hit{}));
    EXPECT_FALSE(arbiter.candidate_within_rounding(centre, right, Hit{2.0f, 0.25f, 0.25f, 1}));
    // An invented hit: the ray through (0.6, 0.5) misses triangle 0 by 0.07.
    const Ray outside = down(0.6f, 0.5f);
    EXPECT_FALSE(arbiter.candidate_within_rounding(outside, Hit{}, Hit{1.0f, 0.6f, 0.5f, 0}));
    // The right triangle at a t off by 1%: its point lies 0.01 from the plane.
    EXPECT_FALSE(arbiter.candidate_within_rounding(centre, right, Hit{1.01f, 0.25f, 0.25f, 0}));
}

TEST(Arbiter, RoundingIsSettled) {
    const Scene s = two_triangles();
    const RoundingArbiter arbiter(s);
    // A ray 1e-7 inside the edge y = 0 (delta there is 9.5e-7): either answer is rounding.
    const Ray edge = down(0.5f, 1e-7f);
    EXPECT_FALSE(arbiter.certain(edge, 0));
    const Hit front{1.0f, 0.5f, 1e-7f, 0}, behind{2.0f, 0.5f, 1e-7f, 1};
    EXPECT_TRUE(arbiter.candidate_within_rounding(edge, front, behind));
    EXPECT_TRUE(arbiter.candidate_within_rounding(edge, behind, front)) << "the reference missed the edge";
    // 1e-3 inside the same edge is no longer rounding.
    const Ray inside = down(0.5f, 1e-3f);
    EXPECT_TRUE(arbiter.certain(inside, 0));
    EXPECT_FALSE(arbiter.candidate_within_rounding(inside, Hit{1.0f, 0.5f, 1e-3f, 0}, Hit{2.0f, 0.5f, 1e-3f, 1}));
    // The right triangle at a t one ulp off is rounding; a hit the reference missed well inside
    // it is not (the reference is wrong there, and the report must say so).
    EXPECT_TRUE(arbiter.candidate_within_rounding(down(0.25f, 0.25f), Hit{1.0f, 0, 0, 0},
                                                  Hit{std::nextafter(1.0f, 2.0f), 0, 0, 0}));
    EXPECT_FALSE(arbiter.candidate_within_rounding(down(0.25f, 0.25f), Hit{2.0f, 0, 0, 1}, Hit{1.0f, 0, 0, 0}));
    EXPECT_FALSE(arbiter.candidate_within_rounding(down(0.25f, 0.25f), Hit{}, Hit{1.0f, 0, 0, 0}));
    // A triangle hit at t = 1 lies outside [0, 0.5]: not certain, so a miss is right there.
    Ray short_ray = down(0.25f, 0.25f);
    short_ray.tmax = 0.5f;
    EXPECT_FALSE(arbiter.certain(short_ray, 0));
}

TEST(Arbiter, InstancesAreJudgedInTheWorld) {
    Scene s = two_triangles();
    // Instance 0 mirrors x and moves by (10, 0, 0): its triangle 0 covers x in [9, 10]; instance 1
    // scales by 2 and lifts by 5 in z: its triangle 0 lies at z = 5 over [0, 2] x [0, 2].
    Affine mirror;
    mirror.m[0][0] = -1.0f;
    mirror.m[0][3] = 10.0f;
    Affine lift;
    for (int a = 0; a < 3; ++a) lift.m[a][a] = 2.0f;
    lift.m[2][3] = 5.0f;
    s.add_instance(0, mirror);
    s.add_instance(0, lift);
    const RoundingArbiter arbiter(s);
    // Flattened ids: instance 0 holds 0 and 1, instance 1 holds 2 and 3.
    const Ray into_mirror = down(9.75f, 0.25f);
    const RoundingArbiter::Verdict v = arbiter.judge(into_mirror, 0, 1.0);
    ASSERT_TRUE(v.triangle);
    EXPECT_NEAR(v.depth, 0.25, 1e-12);
    EXPECT_TRUE(arbiter.certain(into_mirror, 0));
    EXPECT_FALSE(arbiter.certain(down(0.25f, 0.25f), 0)) << "the prototype's own place is empty";
    // Instance 1's triangle 0 at z = 5: the ray from z = 10 meets it at t = 5, 0.5 from its edges.
    const Ray from_above{{0.5f, 0.5f, 10.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, INFINITY};
    EXPECT_NEAR(arbiter.judge(from_above, 2, 5.0).t, 5.0, 1e-12);
    EXPECT_NEAR(arbiter.judge(from_above, 2, 5.0).depth, 0.5, 1e-12);
    EXPECT_TRUE(arbiter.possible(from_above, Hit{5.0f, 0, 0, 2}));
    EXPECT_FALSE(arbiter.possible(from_above, Hit{9.0f, 0, 0, 2})) << "the prototype's t, transform ignored";
    EXPECT_FALSE(arbiter.judge(from_above, 4, 5.0).triangle) << "past the instances' ids";
}

TEST(Arbiter, ShapesAreNeverSettled) {
    Scene s;
    s.name = "ball";
    s.add_shape(Sphere{{0, 0, 0}, 1});
    const RoundingArbiter arbiter(s);
    const Ray r{{0, 0, 5}, 0.0f, {0, 0, -1}, INFINITY};
    EXPECT_FALSE(arbiter.judge(r, 0, 4.0).triangle);
    EXPECT_FALSE(arbiter.candidate_within_rounding(r, Hit{4.0f, 0, 0, 0}, Hit{}));
}

TEST(Arbiter, AgreementCountsSettledRaysApart) {
    const Scene s = two_triangles();
    const RoundingArbiter arbiter(s);
    const std::vector<Ray> rays{down(0.25f, 0.25f), down(0.5f, 1e-7f), down(0.25f, 0.25f)};
    const std::vector<Hit> reference{{1.0f, 0, 0, 0}, {1.0f, 0, 0, 0}, {1.0f, 0, 0, 0}};
    // Ray 1: an edge ray answered with the triangle behind (settled); ray 2: a dropped hit.
    const std::vector<Hit> candidate{{1.0f, 0, 0, 0}, {2.0f, 0, 0, 1}, {}};
    const HitArbiter settle = [&](size_t i, const Hit& r, const Hit& c) {
        return arbiter.candidate_within_rounding(rays[i], r, c);
    };
    const Agreement without = compare_hits(reference, candidate);
    EXPECT_EQ(without.disagreeing(), 2u);
    EXPECT_EQ(without.arbitrated, 0u);
    const Agreement with = compare_hits(reference, candidate, {}, {}, settle);
    EXPECT_EQ(with.agreeing, 2u);
    EXPECT_EQ(with.arbitrated, 1u);
    EXPECT_EQ(with.first_mismatch, 2u);
    // Flags: the arbiter is asked only where they differ.
    std::vector<size_t> asked;
    const Agreement flags = compare_occlusion(std::vector<uint8_t>{1, 0, 1}, std::vector<uint8_t>{1, 1, 0},
                                              {}, [&](size_t i) {
                                                  asked.push_back(i);
                                                  return i == 1;
                                              });
    EXPECT_EQ(asked, (std::vector<size_t>{1, 2}));
    EXPECT_EQ(flags.agreeing, 2u);
    EXPECT_EQ(flags.arbitrated, 1u);
    EXPECT_EQ(flags.first_mismatch, 2u);
}

/// Two triangles sharing the diagonal of the unit square at z = 0: 0 = (0,0),(1,0),(1,1) below
/// it, 1 = (0,0),(1,1),(0,1) above, the shared vertices repeated (as an unwelded export has them).
Scene square() {
    Scene s;
    s.name = "square";
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.indices = {0, 1, 2, 3, 4, 5};
    s.add_mesh(m);
    return s;
}

TEST(Arbiter, ACrackBetweenTwoTrianglesIsNoExcuse) {
    const Scene s = square();
    const RoundingArbiter arbiter(s);
    // On the shared diagonal (1e-7 below it): each triangle alone is within rounding of its edge,
    // but every nearby ray crosses one of the two. The planted bug: a traversal that skipped the
    // node holding both, answering a miss.
    const Ray crack = down(0.5f, 0.5f - 1e-7f);
    EXPECT_TRUE(arbiter.certain(crack, 0)) << "the union of the two covers the crack";
    EXPECT_FALSE(arbiter.candidate_within_rounding(crack, Hit{1.0f, 0, 0, 0}, Hit{}));
    EXPECT_FALSE(arbiter.candidate_within_rounding(crack, Hit{}, Hit{1.0f, 0, 0, 0})) << "the reference skipped it";
    // Either triangle at the crack is rounding.
    EXPECT_TRUE(arbiter.candidate_within_rounding(crack, Hit{1.0f, 0, 0, 0}, Hit{1.0f, 0, 0, 1}));
    EXPECT_TRUE(arbiter.candidate_within_rounding(crack, Hit{1.0f, 0, 0, 1}, Hit{1.0f, 0, 0, 0}));
    // 1e-7 inside the square's outer edge y = 0: no triangle beyond it, a miss is rounding.
    const Ray rim = down(0.7f, 1e-7f);
    EXPECT_FALSE(arbiter.certain(rim, 0));
    EXPECT_TRUE(arbiter.candidate_within_rounding(rim, Hit{1.0f, 0, 0, 0}, Hit{}));
    EXPECT_TRUE(arbiter.candidate_within_rounding(rim, Hit{}, Hit{1.0f, 0, 0, 0}));
    // Folded: triangle 1 turned down about the diagonal until, seen from above, it lies over
    // triangle 0; the shared edge then bounds both, and a ray 1e-7 inside it (inside both
    // projections) may miss both by rounding: a rule that took every shared edge as interior
    // would call it certain.
    Scene folded = square();
    folded.mesh.positions[5] = Vec3(1.0f, 0.2f, -0.5f);
    const RoundingArbiter fold_arbiter(folded);
    const Ray in_fold = down(0.5f, 0.5f - 1e-7f);
    EXPECT_GT(fold_arbiter.judge(in_fold, 1, 1.0).depth, 0.0) << "inside the folded triangle's projection too";
    EXPECT_FALSE(fold_arbiter.certain(in_fold, 0));
    EXPECT_TRUE(fold_arbiter.candidate_within_rounding(in_fold, Hit{1.0f, 0, 0, 0}, Hit{}));
}

TEST(Arbiter, HitsOutsideTheRaysIntervalAreNeverPossible) {
    const Scene s = two_triangles();
    const RoundingArbiter arbiter(s);
    // Triangle 0 lies at t = 1 on this ray; the planted bug reports it on a ray that ends at 0.5
    // or starts at 1.5 (the point is on the triangle: only the interval can refuse it).
    Ray shorter = down(0.25f, 0.25f);
    shorter.tmax = 0.5f;
    EXPECT_FALSE(arbiter.possible(shorter, Hit{1.0f, 0.25f, 0.25f, 0}));
    EXPECT_FALSE(arbiter.candidate_within_rounding(shorter, Hit{}, Hit{1.0f, 0.25f, 0.25f, 0}));
    Ray later = down(0.25f, 0.25f);
    later.tmin = 1.5f;
    EXPECT_FALSE(arbiter.possible(later, Hit{1.0f, 0.25f, 0.25f, 0}));
    // At tmax within rounding: possible.
    Ray ending = down(0.25f, 0.25f);
    ending.tmax = std::nextafter(1.0f, 0.0f);
    EXPECT_TRUE(arbiter.possible(ending, Hit{1.0f, 0.25f, 0.25f, 0}));
}

TEST(Arbiter, AnyHitAnswersAreSettledOnAnyHitAnswers) {
    const Scene s = two_triangles();
    const RoundingArbiter arbiter(s);
    const Ray centre = down(0.25f, 0.25f);
    const Hit inside{1.0f, 0.25f, 0.25f, 0};
    // The planted bug: a candidate whose any-hit path says "not occluded" while its closest-hit
    // path (and the reference) find the triangle's middle. Settled on closest hits it passed.
    EXPECT_FALSE(arbiter.occlusion_within_rounding(centre, false, inside, inside));
    EXPECT_FALSE(arbiter.occlusion_within_rounding(centre, false, Hit{}, inside)) << "its own closest hit betrays it";
    // An occluder the candidate invents (no closest hit names one), or a certain one the
    // reference missed.
    EXPECT_FALSE(arbiter.occlusion_within_rounding(down(0.6f, 0.5f), true, Hit{}, Hit{}));
    EXPECT_FALSE(arbiter.occlusion_within_rounding(centre, true, Hit{}, inside));
    // Within rounding of the edge: either answer.
    const Ray edge = down(0.5f, 1e-7f);
    const Hit at_edge{1.0f, 0.5f, 1e-7f, 0};
    Ray edge_shadow = edge;
    edge_shadow.tmax = 1.5f;  // ends before the triangle behind
    EXPECT_TRUE(arbiter.occlusion_within_rounding(edge_shadow, false, at_edge, Hit{}));
    EXPECT_TRUE(arbiter.occlusion_within_rounding(edge_shadow, true, Hit{}, at_edge));
}

TEST(Arbiter, AMissingInstanceTransformAndIllConditionedInstancesAreNotForgiven) {
    Scene s = two_triangles();
    // One instance moving the two triangles by (10, 0, 0): the planted bug is a reference that
    // ignores the transform and misses there, or answers at the prototype's place.
    Affine moved;
    moved.m[0][3] = 10.0f;
    s.add_instance(0, moved);
    // A second one stretched 50x in x and squeezed 50x in y (condition number 2,500).
    Affine stretched;
    stretched.m[0][0] = 50.0f;
    stretched.m[1][1] = 0.02f;
    stretched.m[2][3] = -10.0f;
    s.add_instance(0, stretched);
    const RoundingArbiter arbiter(s);
    const Ray into = down(10.25f, 0.25f);
    const Hit right{1.0f, 0.25f, 0.25f, 0};
    EXPECT_FALSE(arbiter.candidate_within_rounding(into, Hit{}, right)) << "the reference missed a certain hit";
    EXPECT_FALSE(arbiter.candidate_within_rounding(down(0.25f, 0.25f), Hit{1.0f, 0.25f, 0.25f, 0}, Hit{}))
        << "the prototype's place is empty: the reference's hit is impossible there";
    // The stretched instance's delta is widened 16 times at most, not cond / 3 = 833 times.
    const RoundingArbiter::Verdict v = arbiter.judge(down(25.0f, 0.0025f), 2, 11.0);
    ASSERT_TRUE(v.triangle);
    EXPECT_DOUBLE_EQ(v.scale, kArbiterMaxScale);
}

}  // namespace arbiter_test
