// The conformance suite's agreement rule must flag every classic way a structure goes wrong while
// still looking plausible: a leaf slot mapped to the wrong global id (the right t, the wrong
// primitive), a shifted distance, swapped barycentrics, a dropped hit, an invented one.
#include <gtest/gtest.h>

#include <functional>
#include <type_traits>
#include <memory>
#include <set>
#include <tuple>

#include "support/probe.h"
#include "support/reference.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"

namespace thicket::testing::agreement_rule_test {
namespace {

/// A correct structure whose closest-hit answers pass through `damage`.
class Broken final : public AccelBase<Broken> {
public:
    Broken(std::unique_ptr<Accel> inner, std::function<Hit(const Ray&, Hit)> damage)
        : inner_(std::move(inner)), damage_(std::move(damage)) {
        set_origin(inner_->spec(), 0.0);
    }
    Aabb bounds() const override { return inner_->bounds(); }
    template <class C>
    Hit closest(const Ray& ray, C& counters) const {
        RayCounters c;
        const Hit hit = damage_(ray, inner_->intersect(ray, c));
        if constexpr (std::is_same_v<C, RayCounters>) counters += c;
        return hit;
    }
    template <class C>
    bool any(const Ray& ray, C&) const {
        return inner_->occluded(ray);
    }
    AccelStats stats() const override { return inner_->stats(); }

private:
    std::unique_ptr<Accel> inner_;
    std::function<Hit(const Ray&, Hit)> damage_;
};

class AgreementRule : public ::testing::Test {
protected:
    // The random soup: many hits, few ties.
    const Scene scene = nasty_scenes().back();
    const Reference& ref = reference_for("agreement-rule", scene, "moller", 3000);

    std::string verdict(std::function<Hit(const Ray&, Hit)> damage) const {
        const Broken broken(build_accel("bvh", scene), std::move(damage));
        return compare_with_reference(broken, ref, scene.name);
    }
};

TEST_F(AgreementRule, TheCorrectStructurePasses) {
    EXPECT_EQ(verdict([](const Ray&, Hit h) { return h; }), "");
}

TEST_F(AgreementRule, AWrongIdAtTheRightDistanceIsFlagged) {
    const uint32_t n = uint32_t(scene.primitive_count());
    EXPECT_NE(verdict([n](const Ray&, Hit h) {
                  if (h.found()) h.prim = (h.prim + 1) % n;
                  return h;
              }),
              "");
}

TEST_F(AgreementRule, AShiftedDistanceIsFlagged) {
    EXPECT_NE(verdict([](const Ray&, Hit h) {
                  if (h.found()) h.t *= 1.0f + 2e-6f;  // inside the tie tolerance, so only identity catches it
                  return h;
              }),
              "");
}

TEST_F(AgreementRule, SwappedBarycentricsAreFlagged) {
    EXPECT_NE(verdict([](const Ray&, Hit h) {
                  std::swap(h.u, h.v);
                  return h;
              }),
              "");
}

TEST_F(AgreementRule, ADroppedHitIsFlagged) {
    size_t count = 0;
    EXPECT_NE(verdict([count](const Ray& r, Hit h) mutable { return h.found() && count++ == 100 ? miss_for(r) : h; }),
              "");
}

TEST_F(AgreementRule, AnInventedHitIsFlagged) {
    EXPECT_NE(verdict([](const Ray& r, Hit h) { return h.found() ? h : Hit{r.tmin, 0.5f, 0.25f, 0}; }), "");
}

TEST_F(AgreementRule, ARealTieIsAccepted) {
    // Two copies of one triangle: both are hit at the same t, u, v, so either answer is right.
    Scene twins;
    twins.name = "twins";
    twins.mesh.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}};
    twins.mesh.indices = {0, 1, 2, 0, 1, 2};
    const PrimitiveProbe probe(twins, "moller");
    const Ray ray{{0, 0, 1}, 0.0f, {0, 0, -1}, kInfinity};
    const Hit first = probe.hit(0, ray), second = probe.hit(1, ray);
    ASSERT_TRUE(first.found());
    EXPECT_TRUE(same_closest_hit(second, first, ray, probe));
    // The same t reported for a primitive that is not there is no tie.
    Hit ghost = first;
    ghost.prim = 1;
    ghost.u += 0.125f;
    EXPECT_FALSE(same_closest_hit(ghost, first, ray, probe));
}


// Real scenes get 10^4 rays of which brute force answers only some (reference_for's fast
// reference): an error on a ray brute force did not answer must still be caught, judged by brute
// force then, and a correct structure must still pass.
TEST(FastReference, ErrorsOnRaysBruteForceDidNotAnswerAreCaught) {
    const Scene scene = nasty_scenes().back();
    const Reference& ref = reference_for("fast-reference", scene, "moller", 3000, 300);
    ASSERT_EQ(ref.brute_stride, 10u);
    // The rays brute force did not answer, by their bits (the damage sees only the ray).
    auto off_brute = std::make_shared<std::set<std::tuple<float, float, float, float, float, float>>>();
    for (size_t i = 0; i < ref.rays.size(); ++i)
        if (i % 10 == 5) {
            const Ray& r = ref.rays[i];
            off_brute->insert({r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z});
        }
    const Broken correct(build_accel("bvh:builder=sweep-sah", scene), [](const Ray&, Hit h) { return h; });
    EXPECT_EQ(compare_with_reference(correct, ref, scene.name), "");
    const Broken dropping(build_accel("bvh:builder=sweep-sah", scene), [off_brute](const Ray& r, Hit h) {
        return off_brute->count({r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z}) ? Hit{} : h;
    });
    EXPECT_NE(compare_with_reference(dropping, ref, scene.name), "");
}

TEST(SahExemption, OnlyTheNamedKeyExplainsAMissingSahCost) {
    AccelStats s;
    s.extra.emplace_back("builder SAH cost", "51.2");  // a figure that merely mentions the SAH
    EXPECT_FALSE(sah_cost_explained(s));
    s.extra.emplace_back(kSahUndefinedKey, "");
    EXPECT_FALSE(sah_cost_explained(s)) << "an empty reason explains nothing";
    s.extra.back().second = "oblique cells";
    EXPECT_TRUE(sah_cost_explained(s));
}

}  // namespace
}  // namespace thicket::testing::agreement_rule_test
