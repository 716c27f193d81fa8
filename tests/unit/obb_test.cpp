// The OBB tree: its boxes hold their primitives, it visits fewer nodes than the bvh it came from
// where geometry is long, thin and diagonal, its world-axes fit reproduces the bvh, and a
// corrupted payload is refused.
#include <gtest/gtest.h>

#include <sstream>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/obb/obb.h"
#include "thicket/prims/triangles.h"

namespace thicket::obb_test {
namespace {

const Scene& scene_named(const std::string& name) {
    static const std::vector<Scene> scenes = testing::nasty_scenes();
    for (const Scene& s : scenes)
        if (s.name == name) return s;
    throw Error("no nasty scene " + name);
}

/// Node visits per ray of `spec` on the scene's conformance rays.
double visits_per_ray(const std::string& spec, const Scene& scene) {
    const auto accel = build_accel(spec, scene);
    const std::vector<Ray> rays = testing::conformance_rays(scene, 2000);
    RayCounters c;
    for (const Ray& r : rays) accel->intersect(r, c);
    return double(c.nodes) / double(rays.size());
}

TEST(Obb, EveryBoxHoldsTheVerticesBelowIt) {
    const Scene& scene = scene_named("thin-diagonal");
    const Obb<Triangles<>> obb(Triangles<>(scene.mesh), ObbBuildOptions{});
    const ObbData& d = obb.data();
    ASSERT_FALSE(d.nodes.empty());
    // Each node's box must hold every vertex of every primitive in its subtree.
    for (size_t n = 0; n < d.nodes.size(); ++n) {
        std::vector<uint32_t> stack{uint32_t(n)};
        while (!stack.empty()) {
            const ObbNode& node = d.nodes[stack.back()];
            stack.pop_back();
            if (!node.is_leaf()) {
                stack.push_back(node.leftFirst);
                stack.push_back(node.leftFirst + 1);
                continue;
            }
            for (uint32_t i = node.leftFirst; i < node.leftFirst + node.count; ++i)
                for (int k = 0; k < 3; ++k) {
                    const Vec3 v = scene.mesh.vertex(d.prim_indices[i], k) - d.nodes[n].center;
                    for (int a = 0; a < 3; ++a)
                        ASSERT_LE(std::fabs(dot(d.nodes[n].axis[a], v)), d.nodes[n].half[a]) << "node " << n;
                }
        }
    }
}

TEST(Obb, FewerVisitsThanTheBvhOnThinDiagonalSticks) {
    const Scene& scene = scene_named("thin-diagonal");
    const double bvh = visits_per_ray("bvh", scene), obb = visits_per_ray("obb", scene);
    EXPECT_LT(obb, 0.8 * bvh) << "bvh " << bvh << " visits per ray, obb " << obb;
    // And a lower SAH cost with its own boxes than with axis-aligned ones on the same tree.
    const AccelStats s = build_accel("obb", scene)->stats();
    double aligned = 0;
    for (const auto& [k, v] : s.extra)
        if (k == "SAH cost with axis-aligned boxes") aligned = std::stod(v);
    EXPECT_GT(aligned, 0.0);
    EXPECT_LT(s.sah_cost, aligned);
}

TEST(Obb, WorldAxesFitVisitsAsManyNodesAsTheBvh) {
    const Scene& scene = scene_named("soup");
    const double bvh = visits_per_ray("bvh:traversal=ordered-distance", scene);
    const double axes = visits_per_ray("obb:fit=axes", scene);
    // The same tree and (up to the margin) the same boxes: within a percent.
    EXPECT_NEAR(axes, bvh, 0.01 * bvh);
}

TEST(Obb, CorruptedPayloadIsRefused) {
    const Scene& scene = scene_named("soup");
    const Obb<Triangles<>> obb(Triangles<>(scene.mesh), ObbBuildOptions{});
    ObbData bad = obb.data();
    bad.nodes[0].axis[0] = Vec3(2, 0, 0);
    EXPECT_THROW(validate_obb(bad, scene.primitive_count()), Error);
    bad = obb.data();
    bad.nodes[0].leftFirst = 0;  // a node its own child
    EXPECT_THROW(validate_obb(bad, scene.primitive_count()), Error);
    std::stringstream bytes;
    write_obb(bytes, obb.data());
    const std::string text = bytes.str();
    std::stringstream cut(text.substr(0, text.size() - 5));
    EXPECT_THROW(read_obb(cut, scene.primitive_count()), Error);
    std::stringstream whole(text);
    EXPECT_NO_THROW(read_obb(whole, scene.primitive_count()));
}

}  // namespace
}  // namespace thicket::obb_test
