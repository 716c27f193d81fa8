// Every structure's choice options come from one typed table: an unknown value is refused both
// when a spec string is parsed and when a hand-made AccelSpec reaches the builder, and both
// errors list the allowed values. One test per registered structure (a new one joins itself).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/core/isa.h"

namespace thicket::option_table_test {
namespace {

/// The message of the Error `f` throws, or "" when it throws none.
template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// Whether `level` is "auto" or an ISA level this CPU runs.
bool cpu_has_level(const std::string& level) {
    if (level == kAutoIsa) return true;
    const std::vector<Isa> levels = cpu_isas();
    return std::any_of(levels.begin(), levels.end(), [&](Isa isa) { return level == isa_name(isa); });
}

/// One triangle: every structure builds over it in no time.
Scene one_triangle() {
    Scene s;
    s.name = "one-triangle";
    s.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    s.mesh.indices = {0, 1, 2};
    return s;
}

class OptionTable : public ::testing::TestWithParam<std::string> {};

TEST_P(OptionTable, UnknownChoiceIsAnErrorListingTheAllowedOnes) {
    const AccelInfo& info = *find_accel(GetParam());
    const Scene scene = one_triangle();
    size_t choice_options = 0;
    for (const OptionInfo& o : info.options) {
        if (o.choices.empty()) continue;
        ++choice_options;
        SCOPED_TRACE(info.name + ":" + o.key);
        std::string allowed;
        for (const std::string& c : o.choices) allowed += (allowed.empty() ? "" : ", ") + c;
        const std::string expected = info.name + ": " + o.key + "=bogus is not allowed; choose one of " + allowed;

        const std::string parsed = error_of([&] { parse_accel_spec(info.name + ":" + o.key + "=bogus"); });
        EXPECT_NE(parsed.find(expected), std::string::npos) << parsed;

        // Every listed value is one the parser and the builder accept, but an ISA level this CPU
        // lacks, and Embree's trees where no Embree builder is installed (only the bench has
        // one): the builder refuses those, saying why.
        for (const std::string& c : o.choices) {
            const std::string error = error_of([&] { build_accel(info.name + ":" + o.key + "=" + c, scene); });
            if (o.key == "isa" && !cpu_has_level(c))
                EXPECT_NE(error.find("isa=" + c + " is not supported by this CPU"), std::string::npos) << error;
            else if (o.key == "tree" && c != "thicket")
                EXPECT_NE(error.find("only `thicket bench` links"), std::string::npos) << error;
            else
                EXPECT_EQ(error, "") << c;
        }

        // A preset option never reaches the builder: the parser expands it.
        if (!o.presets.empty()) continue;
        // Past the parser (a spec built by hand): the builder's table refuses it too, instead of
        // taking some default.
        AccelSpec spec = parse_accel_spec(info.name);
        spec.options[o.key].text = "bogus";
        const std::string built = error_of([&] { build_accel(spec, scene); });
        EXPECT_NE(built.find(expected), std::string::npos) << built;
    }
    EXPECT_GE(choice_options, 1u) << "every structure takes at least isect";
}

TEST_P(OptionTable, DefaultIsOneOfTheChoices) {
    for (const OptionInfo& o : find_accel(GetParam())->options) {
        if (o.choices.empty()) continue;
        EXPECT_NE(std::find(o.choices.begin(), o.choices.end(), o.default_value), o.choices.end())
            << GetParam() << ":" << o.key << " default '" << o.default_value << "'";
    }
}

std::vector<std::string> registered_names() {
    std::vector<std::string> names;
    for (const AccelInfo& info : accel_registry()) names.push_back(info.name);
    return names;
}

INSTANTIATE_TEST_SUITE_P(EveryStructure, OptionTable, ::testing::ValuesIn(registered_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(OptionTable, SpecParsedOnceBuildsTheSameStructure) {
    const Scene scene = one_triangle();
    const AccelSpec spec = parse_accel_spec("bvh:builder=sweep-sah,traversal=stack");
    EXPECT_EQ(build_accel(spec, scene)->spec(), build_accel("bvh:builder=sweep-sah,traversal=stack", scene)->spec());
    AccelSpec unknown;
    unknown.name = "octopus";
    EXPECT_NE(error_of([&] { build_accel(unknown, scene); }).find("unknown acceleration structure 'octopus'"),
              std::string::npos);
}

TEST(OptionTable, ChoiceOptionTakesItsListAndDefaultFromTheTable) {
    enum class Fruit { Apple, Pear, Plum };
    constexpr Choice<Fruit> kFruits[] = {{"apple", Fruit::Apple}, {"pear", Fruit::Pear}, {"plum", Fruit::Plum}};
    const OptionInfo o = choice_option("fruit", "which fruit", Fruit::Pear, kFruits);
    EXPECT_EQ(o.key, "fruit");
    EXPECT_EQ(o.default_value, "pear");
    EXPECT_EQ(o.choices, (std::vector<std::string>{"apple", "pear", "plum"}));
    AccelSpec spec;
    spec.name = "basket";
    spec.options["fruit"] = parse_option_value(spec.name, o, "plum");
    EXPECT_EQ(spec.options["fruit"].choice, 2u) << "the value is parsed once, to its index in the table";
    EXPECT_EQ(spec.choice("fruit", kFruits), Fruit::Plum);
    const std::string refused = "basket: fruit=fig is not allowed; choose one of apple, pear, plum";
    EXPECT_EQ(error_of([&] { parse_option_value(spec.name, o, "fig"); }), refused);
    // A value changed by hand past the parser is refused by the table, not taken as another.
    spec.options["fruit"].text = "fig";
    EXPECT_EQ(error_of([&] { spec.choice("fruit", kFruits); }), refused);
}

}  // namespace
}  // namespace thicket::option_table_test
