// The independent double-precision reference (tests/support/double_reference.h) catches a filter
// that drops genuine hits: brute force passes it, and brute force with some well-conditioned hits
// dropped (what a wrong plausibility filter does) does not.
#include <gtest/gtest.h>

#include <vector>

#include "support/double_reference.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/scene/scene.h"

namespace thicket::testing::double_reference_test {
namespace {

TEST(DoubleReference, ExplainsBruteForceAndFlagsDroppedHits) {
    const Scene scene = load_scene("cornell");
    const std::vector<Ray> rays = conformance_rays(scene, 3000);
    for (const char* isect : {"moller", "watertight"}) {
        std::vector<Hit> hits(rays.size());
        build_accel(std::string("brute:isect=") + isect, scene)->intersect(rays, hits);
        const FilterCheck honest = check_against_double_reference(scene, isect, rays, hits);
        EXPECT_EQ(honest.unexplained, 0u) << isect << ": " << honest.first_unexplained;
        EXPECT_GT(honest.agree, rays.size() * 9 / 10) << isect;

        // A filter that rejects one hit in 25, whatever its conditioning.
        size_t dropped = 0, found = 0;
        for (Hit& h : hits)
            if (h.found() && found++ % 25 == 0) h = Hit{}, ++dropped;
        ASSERT_GT(dropped, 20u);
        const FilterCheck broken = check_against_double_reference(scene, isect, rays, hits);
        EXPECT_GT(broken.unexplained, dropped / 2) << isect << ": most dropped hits are well-conditioned";
    }
}

}  // namespace
}  // namespace thicket::testing::double_reference_test
