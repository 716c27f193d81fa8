#include <gtest/gtest.h>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace thicket::spec_test {
namespace {

std::string error_of(const std::string& spec) {
    try {
        parse_accel_spec(spec);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Spec, DefaultsAndCanonicalForm) {
    const AccelSpec s = parse_accel_spec("bvh");
    EXPECT_EQ(s.get("builder"), "binned-sah");
    EXPECT_EQ(s.get_int("bins"), 8);
    EXPECT_EQ(s.get("traversal"), "ordered-distance");
    EXPECT_EQ(s.get("isect"), "moller");
    const AccelSpec t = parse_accel_spec("bvh:traversal=stack, bins=16");
    EXPECT_EQ(t.get("traversal"), "stack");
    EXPECT_EQ(t.get_int("bins"), 16);
    EXPECT_EQ(t.info, find_accel("bvh")) << "the spec keeps the structure it names";
    EXPECT_EQ(t.options.at("traversal").choice, 1u) << "stack: the second traversal";
    EXPECT_DOUBLE_EQ(t.get_real("budget"), 0.3);
    EXPECT_EQ(parse_accel_spec(t.str()).str(), t.str()) << "canonical form parses to itself";
    EXPECT_EQ(t.str(),
              "bvh:alpha=1e-3,bins=16,budget=0.3,builder=binned-sah,isect=moller,max-leaf=8,optimize=none,passes=3,"
              "precision=float,radius=16,sah-block=1,traversal=stack");
}

TEST(Spec, ErrorsListWhatIsAllowed) {
    EXPECT_NE(error_of("octopus").find("known structures: brute, bvh"), std::string::npos) << error_of("octopus");
    EXPECT_NE(error_of("bvh:colour=red")
                  .find("allowed options: builder, bins, max-leaf, sah-block, traversal, precision, alpha, budget, radius, optimize, "
                        "passes, isect"),
              std::string::npos)
        << error_of("bvh:colour=red");
    EXPECT_NE(error_of("bvh:builder=magic").find("choose one of midpoint, binned-sah, sweep-sah, lbvh, sbvh"),
              std::string::npos);
    // Real-valued options (sbvh's alpha and budget): a number, in range, nothing after it.
    EXPECT_NE(error_of("bvh:alpha=tiny").find("must be a number in [0, 1]"), std::string::npos) << error_of("bvh:alpha=tiny");
    EXPECT_NE(error_of("bvh:budget=4.5").find("must be a number in [0, 4]"), std::string::npos);
    EXPECT_NE(error_of("bvh:budget=0.3x").find("number"), std::string::npos);
    EXPECT_NE(error_of("bvh:budget=nan").find("number"), std::string::npos);
    EXPECT_DOUBLE_EQ(parse_accel_spec("bvh:alpha=2.5e-4").get_real("alpha"), 2.5e-4);
    EXPECT_NE(error_of("bvh:bins=1").find("[2, 256]"), std::string::npos);
    EXPECT_NE(error_of("bvh:bins=eight").find("integer"), std::string::npos);
    EXPECT_NE(error_of("bvh:builder").find("key=value"), std::string::npos);
    EXPECT_NE(error_of("bvh:bins=8,bins=9").find("twice"), std::string::npos);
    EXPECT_NE(error_of("bvh:").find("key=value"), std::string::npos);
}

TEST(Spec, PresetsAreExpandedAndTheSpecRecordsWhatIsBuilt) {
    const AccelSpec high = parse_accel_spec("bvh8:quality=high,max-leaf=2");
    EXPECT_EQ(high.get("builder"), "sbvh");
    EXPECT_EQ(high.get("optimize"), "reinsertion");
    EXPECT_EQ(high.get("max-leaf"), "2") << "keys the preset does not set combine with it";
    EXPECT_EQ(high.get("quality"), "custom") << "the preset stands for the keys it set";
    EXPECT_EQ(parse_accel_spec(high.str()).str(), high.str()) << "the recorded spec parses to itself";
    // A key the preset sets, given its default, is no conflict; any other value is.
    EXPECT_EQ(parse_accel_spec("bvh8:quality=low,builder=binned-sah").get("builder"), "lbvh");
    EXPECT_NE(error_of("bvh8:builder=midpoint,quality=high")
                  .find("bvh8: quality=high sets builder itself; drop builder=midpoint or use quality=custom"),
              std::string::npos)
        << error_of("bvh8:builder=midpoint,quality=high");
    EXPECT_NE(error_of("bvh8:quality=low,bins=32").find("sets bins itself; drop bins=32"), std::string::npos);
    EXPECT_NE(describe_accels().find("quality=high sets builder=sbvh,bins=16,optimize=reinsertion"), std::string::npos);
}

TEST(Spec, AStructureBuiltFromAPresetSavesAndLoadsWithItsRecordedSpec) {
    Scene scene;
    scene.name = "two-triangles";
    scene.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    scene.mesh.indices = {0, 1, 2, 0, 1, 3};
    const auto built = build_accel("bvh8:quality=high", scene);
    EXPECT_EQ(built->spec(), parse_accel_spec("bvh8:builder=sbvh,optimize=reinsertion").str());
    EXPECT_EQ(load_accel_bytes(saved_accel_bytes(*built, scene), scene, "saved")->spec(), built->spec());
}

TEST(Spec, EveryVariantParsesAndIsListed) {
    const auto variants = all_accel_variants();
    EXPECT_GE(variants.size(), 17u);
    for (const auto& v : variants) EXPECT_EQ(error_of(v), "") << v;
    const std::string listing = describe_accels();
    for (const char* word : {"bvh", "brute", "builder=midpoint|binned-sah|sweep-sah", "ordered-centroid", "isect"})
        EXPECT_NE(listing.find(word), std::string::npos) << word;
}

}  // namespace
}  // namespace thicket::spec_test
