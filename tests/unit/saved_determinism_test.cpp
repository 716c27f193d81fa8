// A saved structure is a function of the scene and the spec alone: the same bytes on 1, 2 and 7
// threads and whatever the stack held before the build (bvh8 once saved its nodes' padding, which
// was stack garbage: two runs of `thicket build` gave different files).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <utility>
#include <random>
#include <string>
#include <vector>

#include "saved_bytes.h"
#include "thicket/accel/registry.h"

namespace saved_determinism_test {

using namespace thicket;

namespace {

/// Random triangles, some zero-area (collinear) and some duplicated: the inputs that once made
/// builds differ.
Scene soup_with_degenerates() {
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), small(-0.05f, 0.05f);
    TriangleMesh mesh;
    for (int i = 0; i < 1500; ++i) {
        const Vec3 c{u(rng), u(rng), u(rng)};
        const uint32_t base = uint32_t(mesh.positions.size());
        if (i % 7 == 3) {  // collinear: no area
            const Vec3 d{small(rng), small(rng), small(rng)};
            mesh.positions.insert(mesh.positions.end(), {c, c + d, c + d * 2.0f});
        } else {
            mesh.positions.insert(mesh.positions.end(), {c, c + Vec3{small(rng), small(rng), small(rng)},
                                                          c + Vec3{small(rng), small(rng), small(rng)}});
        }
        mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
        if (i % 11 == 5) mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});  // a duplicate
    }
    Scene scene;
    scene.add_mesh(mesh);
    return scene;
}


}  // namespace

TEST(SavedDeterminism, EverySavedVariantIsTheSameBytesOnAnyThreadsAndStack) {
    const Scene scene = soup_with_degenerates();
    size_t checked = 0;
    for (const std::string& spec : all_accel_variants()) {
        const AccelSpec parsed = parse_accel_spec(spec);
        if (!parsed.info->load) continue;  // cannot be saved
        // tetra's payload records TetGen's running time (its statistics): not a function of the input.
        if (parsed.name == "tetra") continue;
        const std::string one = thicket::testing::saved_after_scribble(spec, scene, 1, 0x00);
        for (const auto& [threads, scribble] : {std::pair{2u, 0xA5}, std::pair{7u, 0x5A}}) {
            const std::string other = thicket::testing::saved_after_scribble(spec, scene, threads, (unsigned char)scribble);
            const auto diff = std::mismatch(one.begin(), one.end(), other.begin(), other.end());
            EXPECT_TRUE(diff.first == one.end() && diff.second == other.end())
                << spec << " on " << threads << " threads: " << one.size() << " and " << other.size()
                << " bytes, first difference at byte " << (diff.first - one.begin());
        }
        ++checked;
    }
    EXPECT_GE(checked, 50u);  // every structure but brute force and tetra, with their variants
}

}  // namespace saved_determinism_test
