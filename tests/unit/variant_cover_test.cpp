// The sanitizer job's thinning of the conformance variants (tests/support/variant_cover.h): it
// must keep every option value of every structure, or a kernel would go unchecked there.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>

#include "support/variant_cover.h"
#include "thicket/accel/registry.h"

namespace thicket::testing::variant_cover_test {
namespace {

std::set<std::string> values_of(const std::vector<std::string>& variants) {
    std::set<std::string> out;
    for (const std::string& v : variants) {
        const size_t colon = v.find(':');
        const std::string name = v.substr(0, colon);
        if (colon == std::string::npos) {
            out.insert(name + "|" + name);
            continue;
        }
        size_t start = colon + 1;
        while (start <= v.size()) {
            const size_t comma = std::min(v.find(',', start), v.size());
            out.insert(name + "|" + v.substr(start, comma - start));
            start = comma + 1;
        }
    }
    return out;
}

TEST(VariantCover, AGridOfBuildersAndTraversalsNeedsOneVariantPerValueOfTheLongerAxis) {
    std::vector<std::string> grid;
    for (const char* b : {"a", "b", "c"})
        for (const char* t : {"x", "y", "z", "w"}) {
            std::string v = "s:builder=";
            v += b;
            v += ",traversal=";
            v += t;
            grid.push_back(v);
        }
    const std::vector<std::string> singles = {"s:isect=watertight", "other"};
    grid.insert(grid.end(), singles.begin(), singles.end());
    const std::vector<std::string> cover = covering_variants(grid);
    EXPECT_EQ(values_of(cover), values_of(grid));
    // 4 traversals need 4 variants (which also cover the 3 builders), plus the two single ones.
    EXPECT_EQ(cover.size(), 6u);
    EXPECT_EQ(cover.front(), "s:builder=a,traversal=x") << "the first variant wins ties";
}

TEST(VariantCover, EveryRegisteredOptionValueStaysCovered) {
    const std::vector<std::string> all = all_accel_variants();
    const std::vector<std::string> cover = covering_variants(all);
    EXPECT_EQ(values_of(cover), values_of(all));
    std::set<std::string> names_all, names_cover;
    for (const std::string& v : all) names_all.insert(v.substr(0, v.find(':')));
    for (const std::string& v : cover) names_cover.insert(v.substr(0, v.find(':')));
    EXPECT_EQ(names_cover, names_all) << "every structure keeps at least one variant";
    EXPECT_LT(cover.size(), all.size());
}

}  // namespace
}  // namespace thicket::testing::variant_cover_test
