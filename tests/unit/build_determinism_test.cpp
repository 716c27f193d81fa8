// Every builder's saved structure is a function of the scene and the spec alone: built twice on
// one thread and once each on 2 and 7 threads, over scenes full of what once made builds differ
// (zero-area triangles of every kind, duplicates, piles of identical centroids, NaN and infinite
// vertices). The big scene is past kParallelNodeSize, so its top nodes are binned and partitioned
// chunk by chunk on several threads, and its subtrees are built as concurrent tasks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "saved_bytes.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh/build.h"

namespace build_determinism_test {

using namespace thicket;

namespace {

/// `count` small random triangles in a unit cube, a quarter of them degenerate in turn: a
/// point, a segment (two corners shared), a duplicate of the previous triangle, and three
/// collinear corners; `pile` more collapsed onto one point (identical centroids, more than a
/// node of block-packing holds) and two using NaN and infinite vertices.
Scene degenerate_scene(int count, int pile) {
    std::mt19937 rng(26);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), small(-0.03f, 0.03f);
    TriangleMesh mesh;
    auto vertex = [&](Vec3 p) {
        mesh.positions.push_back(p);
        return uint32_t(mesh.positions.size() - 1);
    };
    auto triangle = [&](uint32_t a, uint32_t b, uint32_t c) { mesh.indices.insert(mesh.indices.end(), {a, b, c}); };
    for (int i = 0; i < count; ++i) {
        const Vec3 c{u(rng), u(rng), u(rng)};
        const uint32_t a = vertex(c), b = vertex(c + Vec3{small(rng), small(rng), small(rng)});
        switch (i % 8) {
        case 1: triangle(a, a, a); break;  // a point
        case 3: triangle(a, b, a); break;  // a segment
        case 5: {                          // the previous triangle again
            const size_t n = mesh.indices.size();
            triangle(mesh.indices[n - 3], mesh.indices[n - 2], mesh.indices[n - 1]);
            break;
        }
        case 7: triangle(a, b, vertex(c + (mesh.positions[b] - c) * 2.0f)); break;  // collinear
        default: triangle(a, b, vertex(c + Vec3{small(rng), small(rng), small(rng)}));
        }
    }
    const uint32_t point = vertex({0.25f, 0.25f, 0.25f});
    for (int i = 0; i < pile; ++i) triangle(point, point, point);
    const uint32_t nan = vertex({std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f});
    const uint32_t inf = vertex({std::numeric_limits<float>::infinity(), 0.0f, 0.0f});
    triangle(nan, 0, 1);
    triangle(inf, 1, 2);
    Scene scene;
    scene.add_mesh(mesh);
    return scene;
}


/// Bytes that differ at the same offset of `a` and `b`.
size_t differing_bytes(const std::string& a, const std::string& b) {
    size_t n = 0;
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) n += a[i] != b[i] ? 1 : 0;
    return n;
}

/// Builds `spec` on 1 thread twice (the stack scribbled differently) and on 2 and 7 threads;
/// every file must be the first one's bytes. Sanitized builds (there for memory errors, which the
/// 7-thread build's concurrent subtrees exercise) build on 1 and 7 threads only.
void expect_same_bytes(const std::string& spec, const Scene& scene) {
    const std::string first = thicket::testing::saved_after_scribble(spec, scene, 1, 0x00);
    ASSERT_GT(first.size(), 0u) << spec;
#ifdef THICKET_SANITIZED
    const std::pair<unsigned, int> others[] = {{7u, 0xFF}};
#else
    const std::pair<unsigned, int> others[] = {{1u, 0xA5}, {2u, 0x5A}, {7u, 0xFF}};
#endif
    for (const auto& [threads, scribble] : others) {
        const std::string other = thicket::testing::saved_after_scribble(spec, scene, threads, (unsigned char)scribble);
        const auto diff = std::mismatch(first.begin(), first.end(), other.begin(), other.end());
        EXPECT_TRUE(diff.first == first.end() && diff.second == other.end())
            << spec << " on " << threads << " thread(s): " << first.size() << " and " << other.size()
            << " bytes, first difference at byte " << (diff.first - first.begin()) << ", "
            << differing_bytes(first, other) << " bytes differ";
    }
}

/// The choices of option `key` of structure `name`, as registered.
std::vector<std::string> choices_of(const std::string& name, const std::string& key) {
    for (const OptionInfo& o : parse_accel_spec(name).info->options)
        if (o.key == key) return o.choices;
    return {};
}

}  // namespace

TEST(BuildDeterminism, EveryBinaryBuilderOfBvhAndBvh8OnABigSceneWithDegenerates) {
    // Over two top nodes' worth of primitives: chunked binning and partitions, concurrent subtrees.
    const Scene scene = degenerate_scene(2 * int(kParallelNodeSize) + 3000, 300);
    ASSERT_GT(scene.primitive_count(), 2 * size_t(kParallelNodeSize));
    std::vector<std::string> specs;
    for (const std::string name : {"bvh", "bvh8"}) {
        const std::vector<std::string> builders = choices_of(name, "builder");
        ASSERT_GE(builders.size(), 5u) << name;
        for (const std::string& builder : builders) specs.push_back(name + ":builder=" + builder);
        // The optimizer rewires any builder's tree alike: after a top-down and a Morton build.
        specs.push_back(name + ":builder=binned-sah,optimize=reinsertion");
        specs.push_back(name + ":builder=lbvh,optimize=reinsertion");
    }
    // Leaves weighed in blocks for bvh, one by one for bvh8, and leaves of several blocks.
    const std::vector<std::string> blocks = {"bvh:builder=binned-sah,sah-block=4",
                                             "bvh:builder=sweep-sah,sah-block=4,max-leaf=16",
                                             "bvh8:builder=binned-sah,sah-block=1",
                                             "bvh8:builder=sweep-sah,max-leaf=16,leaf-merge=8"};
    specs.insert(specs.end(), blocks.begin(), blocks.end());
    for (const std::string& quality : choices_of("bvh8", "quality")) specs.push_back("bvh8:quality=" + quality);
    for (const std::string& spec : specs) expect_same_bytes(spec, scene);
}

TEST(BuildDeterminism, EverySavedStructureAndVariantOnASceneWithDegenerates) {
    const Scene scene = degenerate_scene(2000, 100);
    size_t structures = 0, specs = 0;
    for (const AccelInfo& info : accel_registry()) {
        if (!info.load) continue;            // cannot be saved
        if (info.name == "tetra") continue;  // its payload records TetGen's running time
        ++structures;
        expect_same_bytes(info.name, scene);
        for (const std::string& spec : all_accel_variants())
            if (parse_accel_spec(spec).info == &info) {
                expect_same_bytes(spec, scene);
                ++specs;
            }
    }
    EXPECT_GE(structures, 8u);  // bvh, bvh8, grid, grid2, octree, bsp, kdtree, bih, obb at least
    EXPECT_GE(specs, 50u);      // with their conformance variants
}

}  // namespace build_determinism_test
