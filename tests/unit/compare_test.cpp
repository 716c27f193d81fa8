// `thicket compare`'s library parts: the growth exponent fit, the growth sizes, scenes of a chosen
// size, the default structure list, the growth sweep, the SVG charts (well-formed, one series per
// structure) and the report's tables and JSON.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "support/xml_check.h"
#include "thicket/accel/registry.h"
#include "thicket/bench/compare.h"
#include "thicket/bench/compare_report.h"
#include "thicket/bench/growth_fit.h"
#include "thicket/bench/scene_sizes.h"
#include "thicket/bench/svg_plot.h"
#include "thicket/core/error.h"
#include "thicket/prims/teapot_patches.h"
#include "thicket/scene/scene.h"

namespace compare_test {

using namespace thicket;
using thicket::test::attribute_values;
using thicket::test::xml_wellformedness_error;

namespace {

const Scene& cornell() {
    static const Scene scene = load_scene("cornell");
    return scene;
}

double area(const Scene& s, size_t i) {
    const Vec3 a = s.mesh.vertex(i, 0), b = s.mesh.vertex(i, 1), c = s.mesh.vertex(i, 2);
    const Vec3 n = cross(b - a, c - a);
    return 0.5 * std::sqrt(double(dot(n, n)));
}

size_t count(const std::string& doc, const std::string& needle) {
    size_t n = 0;
    for (size_t p = doc.find(needle); p != std::string::npos; p = doc.find(needle, p + 1)) ++n;
    return n;
}

}  // namespace

TEST(GrowthFit, ExactPowerLawGivesItsExponentBack) {
    for (double k : {0.5, 1.0, 1.5, 2.0}) {
        std::vector<double> n, y;
        for (double x = 1e3; x <= 1e6; x *= 3.1) {
            n.push_back(x);
            y.push_back(3.0 * std::pow(x, k));
        }
        const PowerFit f = fit_power_law(n, y);
        ASSERT_TRUE(f.valid());
        EXPECT_NEAR(f.exponent, k, 1e-9);
        EXPECT_NEAR(f.coefficient, 3.0, 3e-8);
        EXPECT_NEAR(f.r2, 1.0, 1e-12);
        EXPECT_EQ(f.points, n.size());
        EXPECT_EQ(f.min_n, 1e3);
    }
}

TEST(GrowthFit, NLogNOverTheDefaultFitRangeIsSlightlyAboveLinear) {
    const std::vector<double> n{1e3, 3e3, 1e4, 3e4, 1e5, 3e5, 1e6};
    std::vector<double> y;
    for (double x : n) y.push_back(2e-4 * x * std::log(x));
    const PowerFit f = fit_power_law(n, y, double(kDefaultFitMinSize));
    ASSERT_TRUE(f.valid());
    EXPECT_EQ(f.points, 5u) << "only sizes >= 10^4 are fitted";
    EXPECT_EQ(f.min_n, 1e4);
    EXPECT_EQ(f.max_n, 1e6);
    EXPECT_GT(f.exponent, 1.07);
    EXPECT_LT(f.exponent, 1.10);
    EXPECT_GT(f.r2, 0.999);
}

TEST(GrowthFit, PointsThatCannotBeFittedAreIgnoredOrReported) {
    // Non-positive and non-finite points are left out, not fitted as garbage.
    const std::vector<double> n{0, 100, 1000, 10000, 1e5};
    const std::vector<double> y{5, 1, 10, 100, NAN};
    const PowerFit f = fit_power_law(n, y);
    EXPECT_EQ(f.points, 3u);
    EXPECT_NEAR(f.exponent, 1.0, 1e-12);

    const std::vector<double> one_n{1e4}, one_y{2};
    EXPECT_FALSE(fit_power_law(one_n, one_y).valid());
    EXPECT_TRUE(std::isnan(fit_power_law(one_n, one_y).exponent));
    const std::vector<double> same_n{1e4, 1e4}, same_y{2, 3};
    EXPECT_FALSE(fit_power_law(same_n, same_y).valid()) << "no slope between equal sizes";
    EXPECT_FALSE(fit_power_law(n, y, 1e6).valid()) << "nothing at or above min_n";
    const std::vector<double> short_y{1, 2};
    EXPECT_THROW(fit_power_law(n, short_y), Error);
}

TEST(GrowthSizes, DefaultsAndParsing) {
    EXPECT_EQ(default_growth_sizes(), (std::vector<size_t>{1000, 3000, 10000, 30000, 100000, 300000, 1000000}));
    EXPECT_EQ(default_growth_sizes(200000), (std::vector<size_t>{1000, 3000, 10000, 30000, 100000, 200000}));
    EXPECT_EQ(default_growth_sizes(3000), (std::vector<size_t>{1000, 3000}));
    EXPECT_EQ(default_growth_sizes(500), (std::vector<size_t>{500}));
    EXPECT_THROW(default_growth_sizes(0), Error);

    EXPECT_EQ(parse_size_list("1e4, 1000,1000,2.5e3"), (std::vector<size_t>{1000, 2500, 10000}));
    for (const char* bad : {"abc", "10,1.5", "0", "1e9", "", "100,", "-5", "inf"}) {
        SCOPED_TRACE(bad);
        try {
            parse_size_list(bad);
            ADD_FAILURE() << "accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("size '"), std::string::npos) << e.what();
        }
    }
}

// Issue 16: `thicket compare teapot-patches` crashed here, reading as many triangles as the scene
// has primitives (shapes included).
TEST(SceneOfSize, ShapesAreLeftOutAndAShapesOnlySceneIsAnError) {
    const Scene teapot = load_scene("teapot-patches");
    ASSERT_EQ(teapot.mesh.triangle_count(), 0u);
    try {
        scene_of_size(teapot, 100);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("--no-growth"), std::string::npos) << e.what();
    }
    Scene mixed = cornell();
    for (const BezierPatch& p : teapot_patches()) mixed.add_shape(p);
    const size_t tris = cornell().mesh.triangle_count();
    const Scene bigger = scene_of_size(mixed, 4 * tris);
    EXPECT_EQ(bigger.mesh.triangle_count(), 4 * tris);
    EXPECT_FALSE(bigger.has_shapes());
    EXPECT_EQ(scene_of_size(mixed, tris).mesh.positions, scene_of_size(cornell(), tris).mesh.positions);
}

TEST(SceneOfSize, SubsetKeepsOriginalTrianglesInFileOrder) {
    const Scene& s = cornell();
    const size_t m = s.primitive_count();
    ASSERT_GT(m, 20u);
    const Scene a = scene_of_size(s, 20);
    ASSERT_EQ(a.primitive_count(), 20u);
    // Each output triangle is an input triangle, in increasing input order, none twice.
    size_t next = 0;
    for (size_t i = 0; i < a.primitive_count(); ++i) {
        bool found = false;
        for (; next < m && !found; ++next)
            found = a.mesh.vertex(i, 0) == s.mesh.vertex(next, 0) && a.mesh.vertex(i, 1) == s.mesh.vertex(next, 1) &&
                    a.mesh.vertex(i, 2) == s.mesh.vertex(next, 2);
        EXPECT_TRUE(found) << "triangle " << i << " is not an original triangle in file order";
    }
    const Scene again = scene_of_size(s, 20);
    EXPECT_EQ(again.mesh.positions, a.mesh.positions) << "same seed, same triangles";
    EXPECT_NE(scene_of_size(s, 20, 12345).mesh.positions, a.mesh.positions) << "another seed, another subset";

    const Scene all = scene_of_size(s, m);
    ASSERT_EQ(all.primitive_count(), m);
    for (size_t i = 0; i < m; ++i)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(all.mesh.vertex(i, c), s.mesh.vertex(i, c));
    EXPECT_EQ(scene_of_size(s, 0).primitive_count(), 0u);
}

TEST(SceneOfSize, LargerSizesSubdivideIntoQuarters) {
    const Scene& s = cornell();
    const size_t m = s.primitive_count();
    EXPECT_EQ(subdivision_rounds(m, m), 0);
    EXPECT_EQ(subdivision_rounds(m, m + 1), 1);
    EXPECT_EQ(subdivision_rounds(m, 4 * m), 1);
    EXPECT_EQ(subdivision_rounds(m, 4 * m + 1), 2);
    EXPECT_THROW(subdivision_rounds(0, 1), Error);

    // All of one round: exactly the four quarters of every triangle, so the total area is kept
    // and every quarter has a quarter of its parent's area, in its parent's order.
    const Scene q = scene_of_size(s, 4 * m);
    ASSERT_EQ(q.primitive_count(), 4 * m);
    double total = 0.0, total_q = 0.0;
    for (size_t i = 0; i < m; ++i) {
        total += area(s, i);
        for (size_t k = 0; k < 4; ++k) {
            EXPECT_NEAR(area(q, 4 * i + k), area(s, i) / 4, 1e-5 * area(s, i) + 1e-12) << i << "." << k;
            // Same winding: the normals point the same way.
            EXPECT_GE(dot(q.geometric_normal(uint32_t(4 * i + k)), s.geometric_normal(uint32_t(i))), 0.0f);
        }
    }
    for (size_t i = 0; i < q.primitive_count(); ++i) total_q += area(q, i);
    EXPECT_NEAR(total_q, total, 1e-5 * total);

    // Two rounds and a subset: exact count, all inside the scene's bounds, area 1/16 of a parent's.
    const Scene r = scene_of_size(s, 5 * m);
    ASSERT_EQ(r.primitive_count(), 5 * m);
    std::set<double> parent_areas;
    for (size_t i = 0; i < m; ++i) parent_areas.insert(area(s, i) / 16);
    const Aabb b = s.bounds();
    for (size_t i = 0; i < r.primitive_count(); ++i) {
        for (int c = 0; c < 3; ++c) {
            const Vec3 v = r.mesh.vertex(i, c);
            EXPECT_TRUE(v.x >= b.min.x && v.x <= b.max.x && v.y >= b.min.y && v.y <= b.max.y && v.z >= b.min.z &&
                        v.z <= b.max.z);
        }
        const double a = area(r, i);
        const bool matches = std::any_of(parent_areas.begin(), parent_areas.end(),
                                         [&](double p) { return std::fabs(a - p) <= 1e-5 * p + 1e-12; });
        EXPECT_TRUE(matches) << "triangle " << i << " of area " << a << " is not a sixteenth of an original";
    }

    EXPECT_THROW(scene_of_size(Scene{}, 3), Error);
    EXPECT_THROW(scene_of_size(s, kMaxSceneSize + 1), Error);
}

TEST(CompareSpecs, DefaultListIsEveryStructureButBruteForce) {
    const std::vector<std::string> specs = default_compare_specs();
    EXPECT_NE(std::find(specs.begin(), specs.end(), "bvh"), specs.end());
    EXPECT_EQ(std::find(specs.begin(), specs.end(), "brute"), specs.end());
    // One per registered structure that partitions anything.
    size_t partitioning = 0;
    for (const AccelInfo& info : accel_registry()) partitioning += info.partitioning != Partitioning::None;
    EXPECT_EQ(specs.size(), partitioning);
    for (const std::string& s : specs) {
        EXPECT_NO_THROW(parse_accel_spec(s)) << s;
        EXPECT_NE(spec_partitioning(s), Partitioning::None) << s;
    }
    EXPECT_EQ(spec_partitioning("bvh:builder=midpoint"), Partitioning::Object);
    EXPECT_EQ(spec_partitioning("brute"), Partitioning::None);
    EXPECT_EQ(spec_partitioning("nosuch"), Partitioning::Unknown);
    EXPECT_STREQ(partitioning_name(Partitioning::Space), "space");
}

TEST(CompareGrowth, MeasuresEverySizeWithRealBuilds) {
    // Real builds: every size measured in order, each built at least once and at most max_builds
    // times. Nothing here reads the clock's figures, which a loaded machine may stretch.
    std::vector<Scene> sized;
    for (size_t n : {100, 400, 1600}) sized.push_back(scene_of_size(cornell(), n));
    GrowthOptions options;
    options.max_builds = 2;
    options.build_budget_s = 0.0;  // never stop: the budget rule is checked on counted costs below
    std::vector<size_t> seen;
    const Growth g = measure_growth("bvh", sized, options, [&](const GrowthPoint& p) { seen.push_back(p.n); });
    ASSERT_EQ(g.points.size(), 3u);
    EXPECT_EQ(seen, (std::vector<size_t>{100, 400, 1600}));
    for (const GrowthPoint& p : g.points) {
        EXPECT_GE(p.build_ms, 0.0);
        EXPECT_GE(p.builds, 1);
        EXPECT_LE(p.builds, 2);
    }
    EXPECT_FALSE(g.stopped_at);
    options.max_builds = 0;
    EXPECT_THROW(measure_growth("bvh", sized, options), Error);
}

/// Sizes 100, 400, 1600 and 6400 whose builds cost n^1.5 / 1000 ms, counted instead of timed; each
/// call's scene size is recorded in `built`.
struct CountedGrowth {
    std::vector<Scene> sized;
    std::vector<size_t> built;
    GrowthOptions options;
    CountedGrowth() {
        for (size_t n : {100, 400, 1600, 6400}) sized.push_back(scene_of_size(cornell(), n));
        options.fit_min_size = 100;
        options.build = [this](const std::string& spec, const Scene& scene) {
            EXPECT_EQ(spec, "bvh");
            built.push_back(scene.primitive_count());
            return std::pow(double(scene.primitive_count()), 1.5) / 1000.0;
        };
    }
    Growth run() { return measure_growth("bvh", sized, options); }
};

TEST(CompareGrowth, RepeatsBuildsUntilTheirBudgetAndFitsTheExponent) {
    // Costs 1, 8, 64 and 512 ms. A repeat budget of 20 ms: builds of one size go on until their
    // total reaches it or max_builds is reached, so 5, 3, 1 and 1 builds.
    CountedGrowth c;
    c.options.max_builds = 5;
    c.options.repeat_budget_ms = 20.0;
    c.options.build_budget_s = 0.0;
    const Growth g = c.run();
    ASSERT_EQ(g.points.size(), 4u);
    const int builds[4] = {5, 3, 1, 1};
    for (size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(g.points[i].builds, builds[i]) << g.points[i].n;
        EXPECT_DOUBLE_EQ(g.points[i].build_ms, std::pow(double(g.points[i].n), 1.5) / 1000.0);
    }
    EXPECT_EQ(c.built.size(), 10u);
    EXPECT_TRUE(g.fit.valid());
    EXPECT_NEAR(g.fit.exponent, 1.5, 1e-9);
    EXPECT_EQ(g.fit.points, 4u);
    // fit_min_size leaves the smaller sizes out of the fit.
    c.options.fit_min_size = 1600;
    EXPECT_EQ(c.run().fit.points, 2u);
}

TEST(CompareGrowth, StopsBeforeASizePredictedOverTheBuildBudget) {
    // After 100 and 400 (1 and 8 ms) the slope is 1.5, so 1600 is predicted at 8 * 4^1.5 = 64 ms:
    // a budget of 0.05 s stops there, one of 0.07 s measures it and stops before 6400 (512 ms).
    CountedGrowth c;
    c.options.max_builds = 1;
    c.options.build_budget_s = 0.05;
    Growth g = c.run();
    ASSERT_EQ(g.points.size(), 2u);
    ASSERT_TRUE(g.stopped_at);
    EXPECT_EQ(*g.stopped_at, 1600u);
    EXPECT_NEAR(g.predicted_s, 0.064, 1e-12);
    EXPECT_EQ(c.built, (std::vector<size_t>{100, 400})) << "the stopped size is not built";
    c.options.build_budget_s = 0.07;
    g = c.run();
    ASSERT_EQ(g.points.size(), 3u);
    EXPECT_EQ(g.stopped_at.value_or(0), 6400u);
    EXPECT_NEAR(g.predicted_s, 0.512, 1e-12);
    // A step slower than linear still predicts linear growth: 0.25 ms, 0.5 ms (slope 0.5), then
    // 0.5 * 4 = 2 ms for 1600, over a budget of 1.5 ms (slope 0.5 would have promised 1 ms).
    c.options.build = [](const std::string&, const Scene& scene) {
        const size_t n = scene.primitive_count();
        return n < 200 ? 0.25 : n < 1000 ? 0.5 : 100.0;
    };
    c.options.build_budget_s = 0.0015;
    g = c.run();
    ASSERT_TRUE(g.stopped_at);
    EXPECT_EQ(*g.stopped_at, 1600u);
    EXPECT_NEAR(g.predicted_s, 0.002, 1e-12);
    // With only the first size measured there is nothing to fit.
    c.options.build_budget_s = 1e-12;
    g = c.run();
    ASSERT_EQ(g.points.size(), 1u);
    EXPECT_EQ(g.stopped_at.value_or(0), 400u);
    EXPECT_FALSE(g.fit.valid());
}

TEST(SvgPlot, XmlEscapingAndTheCheckerItself) {
    EXPECT_EQ(xml_escape("a<b & \"c\" 'd'>"), "a&lt;b &amp; &quot;c&quot; &apos;d&apos;&gt;");
    // The checker must be able to fail, or the tests below prove nothing.
    EXPECT_EQ(xml_wellformedness_error("<?xml version=\"1.0\"?>\n<a x=\"1\"><b/>t &amp; u</a>\n"), "");
    for (const char* bad : {"<a><b></a></b>", "<a>", "<a x=1/>", "<a x=\"1\" x=\"2\"/>", "<a>&nope;</a>",
                            "<a/><b/>", "text<a/>", "<a>x & y</a>", "<a x=\"<\"/>", "", "<a></b>"})
        EXPECT_NE(xml_wellformedness_error(bad), "") << bad;
}

TEST(SvgPlot, LogLogPlotHasOnePolylinePerSeries) {
    LogLogPlot plot;
    plot.title = "Build <time> & N";
    plot.x_label = "N";
    plot.y_label = "ms";
    plot.series = {{"bvh", {1e3, 1e4, 1e5}, {0.1, 1.5, 20}},
                   {"a&b \"quoted\"", {1e3, 1e4}, {0.01, 0.2}},
                   {"empty", {}, {}},
                   {"bad points only", {0, -1}, {1, 1}}};
    const std::string svg = svg_log_log_plot(plot);
    EXPECT_EQ(xml_wellformedness_error(svg), "") << svg;
    EXPECT_EQ(attribute_values(svg, "polyline", "data-series"),
              (std::vector<std::string>{"bvh", "a&amp;b &quot;quoted&quot;", "empty", "bad points only"}));
    EXPECT_EQ(count(svg, "<circle"), 5u + 4u) << "a marker per drawable point, plus one per legend entry";
    // Decade ticks from 1k to 100k and 0.01 to 100, labelled.
    for (const char* label : {">1k<", ">10k<", ">100k<", ">0.01<", ">100<"})
        EXPECT_NE(svg.find(label), std::string::npos) << label;
    EXPECT_NE(svg.find("Build &lt;time&gt; &amp; N"), std::string::npos);

    plot.series[0].y.pop_back();
    EXPECT_THROW(svg_log_log_plot(plot), Error);
    EXPECT_EQ(xml_wellformedness_error(svg_log_log_plot(LogLogPlot{})), "") << "no series at all";
}

TEST(SvgPlot, BarChartHasOneBarPerFiniteValue) {
    BarChart chart;
    chart.title = "Mrays/s";
    chart.y_label = "Mrays/s";
    chart.series = {"primary", "diffuse"};
    chart.groups = {{"bvh", {12.5, 3.25}}, {"a-very-long-structure:spec=with,many=options", {0.5, NAN}}};
    const std::string svg = svg_bar_chart(chart);
    EXPECT_EQ(xml_wellformedness_error(svg), "") << svg;
    EXPECT_EQ(attribute_values(svg, "rect", "data-series"),
              (std::vector<std::string>{"primary", "diffuse", "primary"}));
    EXPECT_EQ(attribute_values(svg, "rect", "data-group"),
              (std::vector<std::string>{"bvh", "bvh", "a-very-long-structure:spec=with,many=options"}));
    EXPECT_NE(svg.find(">12.5<"), std::string::npos) << "values are written on the bars";
    EXPECT_NE(svg.find("rotate(-35)"), std::string::npos) << "long group labels are slanted";

    chart.groups[0].values.push_back(1.0);
    EXPECT_THROW(svg_bar_chart(chart), Error);
}

namespace {

CompareRow synthetic_row(const std::string& accel, Partitioning p, double sah, bool with_growth) {
    CompareRow r;
    r.scene = "test.ply";
    r.primitives = 1000;
    r.accel = accel;
    r.spec = accel;
    r.partitioning = p;
    for (const char* set : kCompareSets)
        for (unsigned t : {1u, 2u}) {
            BenchRow b;
            b.scene = r.scene;
            b.primitives = r.primitives;
            b.accel = accel;
            b.spec = accel;
            b.set = set;
            b.threads = t;
            b.mrays = 1.5 * t;
            b.build_ms = 12.0;
            b.structure_bytes = 32000;
            b.sah_cost = sah;
            b.nodes_per_ray = 40.0;
            b.prims_per_ray = 6.0;
            r.speed.push_back(b);
        }
    if (with_growth) {
        Growth g;
        g.points = {{1000, 1.0, 5}, {10000, 11.0, 3}, {100000, 130.0, 1}};
        std::vector<double> n{1000, 10000, 100000}, y{1.0, 11.0, 130.0};
        g.fit = fit_power_law(n, y, 10000);
        r.growth = g;
    }
    return r;
}

}  // namespace

TEST(CompareReport, TablesJsonAndChartsShowEveryRow) {
    const std::vector<CompareRow> rows = {synthetic_row("bvh", Partitioning::Object, 91.5, true),
                                          synthetic_row("spacey", Partitioning::Space, 0.0, true)};
    CompareSettings settings;
    settings.growth.sizes = {1000, 10000, 100000};
    const std::string text = format_compare_tables(rows, settings, TableStyle::Terminal);
    for (const char* needle : {"structure", "partitioning", "growth k", "B/prim", "SAH cost", "primary Mrays/s 1t/2t",
                               "diffuse nodes/prims", "N=10k", "fit over", "bvh ", "spacey ", "object", "space",
                               "91.50", "32.0", "1.50 / 3.00", "40.0 / 6.00"})
        EXPECT_NE(text.find(needle), std::string::npos) << needle << "\n" << text;
    // The SAH cost of the structure without one is a dash, and the exponent is the fitted one.
    const size_t spacey = text.find("\nspacey ");
    ASSERT_NE(spacey, std::string::npos);
    EXPECT_NE(text.substr(spacey, text.find('\n', spacey + 1) - spacey).find("\u2014"), std::string::npos);
    char k[16];
    std::snprintf(k, sizeof k, "%.2f", std::log(130.0 / 11.0) / std::log(10.0));
    EXPECT_NE(text.find(k), std::string::npos) << k;

    const std::string md = format_compare_tables(rows, settings, TableStyle::Markdown);
    EXPECT_NE(md.find("| structure | partitioning |"), std::string::npos) << md;

    const nlohmann::json j = nlohmann::json::parse(compare_json(rows, settings));
    ASSERT_EQ(j["rows"].size(), 2u);
    EXPECT_EQ(j["rows"][0]["partitioning"], "object");
    EXPECT_TRUE(j["rows"][1]["sah_cost"].is_null());
    EXPECT_EQ(j["rows"][0]["growth"]["points"].size(), 3u);
    EXPECT_NEAR(j["rows"][0]["growth"]["exponent"].get<double>(), std::log(130.0 / 11.0) / std::log(10.0), 1e-6);
    EXPECT_EQ(j["rows"][0]["speed"].size(), 4u);
    EXPECT_EQ(j["settings"]["growth_sizes"].size(), 3u);

    const std::string growth = growth_plot_svg(rows);
    EXPECT_EQ(xml_wellformedness_error(growth), "");
    EXPECT_EQ(attribute_values(growth, "polyline", "data-series"), (std::vector<std::string>{"bvh", "spacey"}));
    const std::string speed = speed_plot_svg(rows, settings);
    EXPECT_EQ(xml_wellformedness_error(speed), "");
    EXPECT_EQ(attribute_values(speed, "rect", "data-series").size(), 8u) << "2 sets x 2 thread counts x 2 rows";
}

}  // namespace compare_test
