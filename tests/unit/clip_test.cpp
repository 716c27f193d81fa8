// clip_triangle_to_box: the clipped bounds must enclose every point of the triangle inside the
// box, and lie inside both the box and the triangle's own bounds.
#include <gtest/gtest.h>

#include <random>

#include "thicket/prims/primitive_set.h"
#include "thicket/prims/triangles.h"

namespace thicket::clip_test {
namespace {

bool encloses(const Aabb& outer, Vec3 p) { return outer.contains(p); }

TEST(ClipTriangle, EnclosesEveryInsidePointAndStaysInsideBoxAndTriangle) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> coord(-2.0f, 2.0f), bary(0.0f, 1.0f);
    int nonempty = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const Vec3 a{coord(rng), coord(rng), coord(rng)}, b{coord(rng), coord(rng), coord(rng)},
            c{coord(rng), coord(rng), coord(rng)};
        Aabb box;
        box.grow(Vec3{coord(rng), coord(rng), coord(rng)} * 0.5f);
        box.grow(Vec3{coord(rng), coord(rng), coord(rng)} * 0.5f);
        const Aabb clipped = clip_triangle_to_box(a, b, c, box);
        Aabb tri;
        tri.grow(a);
        tri.grow(b);
        tri.grow(c);
        if (!clipped.empty()) {
            ++nonempty;
            for (int k = 0; k < 3; ++k) {
                EXPECT_GE(clipped.min[k], box.min[k]);
                EXPECT_LE(clipped.max[k], box.max[k]);
                EXPECT_GE(clipped.min[k], std::nextafter(tri.min[k], -INFINITY));
                EXPECT_LE(clipped.max[k], std::nextafter(tri.max[k], INFINITY));
            }
        }
        for (int s = 0; s < 200; ++s) {
            float u = bary(rng), v = bary(rng);
            if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
            const Vec3 p = a + (b - a) * u + (c - a) * v;
            if (box.contains(p)) {
                ASSERT_TRUE(encloses(clipped, p)) << "trial " << trial;
            }
        }
    }
    EXPECT_GT(nonempty, 200);  // the test exercised real clips, not only misses
}

TEST(ClipTriangle, FlatTriangleInBoxFaceIsKept) {
    const Aabb box{{0, 0, 0}, {1, 1, 1}};
    const Aabb r = clip_triangle_to_box({-1, 0.5f, 0}, {2, 0.5f, 0}, {0.5f, 0.5f, 3}, box);
    ASSERT_FALSE(r.empty());
    EXPECT_FLOAT_EQ(r.min.y, 0.5f);
    EXPECT_FLOAT_EQ(r.max.y, 0.5f);
    EXPECT_FLOAT_EQ(r.min.x, 0.0f);
    EXPECT_FLOAT_EQ(r.max.x, 1.0f);
}

TEST(ClipTriangle, ClippedBoundsHookFallsBackForSetsWithoutClip) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};
    mesh.indices = {0, 1, 2};
    const Triangles<> tris(mesh);
    const Aabb box{{2, 2, -1}, {3, 3, 1}};
    // The corner (2..3, 2..3) lies beyond the hypotenuse x + y = 4 except at the point (2, 2).
    const Aabb exact = clipped_bounds(tris, 0, box);
    EXPECT_LE(exact.max.x, 2.0f + 1e-5f);
    EXPECT_LE(exact.max.y, 2.0f + 1e-5f);
    static_assert(kHasTriangles<Triangles<>>);
}

}  // namespace
}  // namespace thicket::clip_test
