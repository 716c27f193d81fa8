#include <gtest/gtest.h>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace thicket {
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
    EXPECT_EQ(parse_accel_spec(t.str()).str(), t.str()) << "canonical form parses to itself";
    EXPECT_EQ(t.str(),
              "bvh:alpha=1e-3,bins=16,budget=0.3,builder=binned-sah,isect=moller,max-leaf=8,optimize=none,passes=3,"
              "traversal=stack");
}

TEST(Spec, ErrorsListWhatIsAllowed) {
    EXPECT_NE(error_of("octopus").find("known structures: brute, bvh"), std::string::npos) << error_of("octopus");
    EXPECT_NE(error_of("bvh:colour=red").find("allowed options: builder, bins, max-leaf, traversal, alpha, budget, optimize, passes, isect"),
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

TEST(Spec, EveryVariantParsesAndIsListed) {
    const auto variants = all_accel_variants();
    EXPECT_GE(variants.size(), 17u);
    for (const auto& v : variants) EXPECT_EQ(error_of(v), "") << v;
    const std::string listing = describe_accels();
    for (const char* word : {"bvh", "brute", "builder=midpoint|binned-sah|sweep-sah", "ordered-centroid", "isect"})
        EXPECT_NE(listing.find(word), std::string::npos) << word;
}

}  // namespace
}  // namespace thicket
