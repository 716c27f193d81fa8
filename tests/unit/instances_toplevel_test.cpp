// The instanced structure's top level (instances/instance_top.h): world boxes from vertex parts
// hold every transformed vertex and are tighter than a turned box's box, and a ray outside them
// calls no instance; a triangle bvh8 bottom is called through its kernels; the 8-wide SAH top level
// over a field of instances visits a path, not the field. Counted work, never time.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "thicket/instances/instance_top.h"
#include "thicket/instances/instances.h"
#include "thicket/accel/registry.h"

namespace instances_toplevel_test {

using namespace thicket;

/// A thin stick along x from -1 to 1 (two triangles of a 0.02-wide strip, cut into 32 pieces so
/// that it has vertices along its length).
std::shared_ptr<const Scene> stick() {
    auto scene = std::make_shared<Scene>();
    scene->name = "stick";
    TriangleMesh m;
    const int pieces = 32;
    for (int i = 0; i <= pieces; ++i) {
        const float x = -1.0f + 2.0f * float(i) / pieces;
        m.positions.push_back({x, 0.0f, -0.01f});
        m.positions.push_back({x, 0.0f, 0.01f});
    }
    for (uint32_t i = 0; i < uint32_t(pieces); ++i) {
        const uint32_t a = 2 * i;
        m.indices.insert(m.indices.end(), {a, a + 2, a + 1, a + 1, a + 2, a + 3});
    }
    scene->add_mesh(m);
    return scene;
}

/// A closed UV sphere of radius 1 about the origin.
std::shared_ptr<const Scene> ball() {
    auto scene = std::make_shared<Scene>();
    scene->name = "ball";
    TriangleMesh m;
    const int rings = 12, segments = 24;
    for (int r = 0; r <= rings; ++r)
        for (int k = 0; k < segments; ++k) {
            const double theta = M_PI * r / rings, phi = 2.0 * M_PI * k / segments;
            m.positions.push_back({float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                                   float(std::sin(theta) * std::sin(phi))});
        }
    auto at = [&](int r, int k) { return uint32_t(r * segments + (k % segments)); };
    for (int r = 0; r < rings; ++r)
        for (int k = 0; k < segments; ++k)
            m.indices.insert(m.indices.end(),
                             {at(r, k), at(r + 1, k), at(r, k + 1), at(r, k + 1), at(r + 1, k), at(r + 1, k + 1)});
    scene->add_mesh(m);
    return scene;
}

/// A turn by `angle` about y, then a move by (x, 0, z).
Affine turned(float angle, float x, float z) {
    Affine t;
    const float c = std::cos(angle), s = std::sin(angle);
    t.m[0][0] = c, t.m[0][2] = s, t.m[0][3] = x;
    t.m[2][0] = -s, t.m[2][2] = c, t.m[2][3] = z;
    return t;
}

}  // namespace instances_toplevel_test

using namespace instances_toplevel_test;

TEST(InstancesTopLevel, VertexPartsHoldEveryVertexAndHugATurnedBall) {
    const auto held = ball();
    const Scene& proto = *held;
    const std::vector<Aabb> parts = vertex_parts(proto, proto.bounds());
    ASSERT_GT(parts.size(), 1u);
    ASSERT_LE(parts.size(), 64u);
    const Affine t = turned(0.785398f, 0.0f, 0.0f);  // an eighth of a turn
    const Aabb tight = transform_parts(t, parts);
    const Aabb loose = transform_box(t, proto.bounds());
    for (const Vec3& p : proto.mesh.positions) {
        const Vec3 w = t.point(p);
        for (int a = 0; a < 3; ++a) {
            EXPECT_LE(tight.min[a], w[a]);
            EXPECT_GE(tight.max[a], w[a]);
        }
    }
    // The turned cube's box reaches sqrt(2) along x and z; the parts stay nearer the ball's 1.
    EXPECT_GT(loose.max.x, 1.4f);
    EXPECT_LT(tight.max.x, 1.25f);
    EXPECT_LT(tight.max.z, 1.25f);
    // A shape scene is one part: its bounds.
    Scene shapes;
    shapes.add_shape(Sphere{{0, 0, 0}, 1.0f});
    EXPECT_EQ(vertex_parts(shapes, shapes.bounds()).size(), 1u);
}

TEST(InstancesTopLevel, ARayInsideATurnedBoxButBesideTheBallCallsNoInstance) {
    // (1.3, 1.3) lies inside the turned cube's box ([-1.41, 1.41] in x and z) and 1.84 from the
    // ball's axis: the top level's box, from vertex parts, keeps that ray out of the instance.
    const InstancedAccel accel(ball(), {{0, turned(0.785398f, 0.0f, 0.0f)}}, "bvh8");
    RayCounters corner, through;
    EXPECT_FALSE(accel.intersect(Ray{{1.3f, 3.0f, 1.3f}, 0.0f, {0.0f, -1.0f, 0.0f}}, corner).found());
    EXPECT_FALSE(accel.occluded(Ray{{1.3f, 3.0f, 1.3f}, 0.0f, {0.0f, -1.0f, 0.0f}}, corner));
    // The root, once per query (the kernel tests its children's boxes), and no instance.
    EXPECT_EQ(corner.nodes, 2u);
    EXPECT_EQ(corner.prims, 0u);
    EXPECT_TRUE(accel.intersect(Ray{{0.2f, 3.0f, 0.1f}, 0.0f, {0.0f, -1.0f, 0.0f}}, through).found());
    EXPECT_GT(through.prims, 1u);  // the instance, then the ball's triangles
}

TEST(InstancesTopLevel, TriangleBvh8BottomsAreCalledThroughTheirKernels) {
    const Scene proto = *stick();
    for (const char* spec : {"bvh8", "bvh8:isect=watertight", "bvh8:nodes=compressed"}) {
        const auto accel = build_accel(spec, proto);
        EXPECT_NE(instance_bottom(*accel).ctx, nullptr) << spec;
    }
    const auto other = build_accel("bvh", proto);
    EXPECT_EQ(instance_bottom(*other).ctx, nullptr);
    EXPECT_EQ(instance_bottom(*other).accel, other.get());
}

TEST(InstancesTopLevel, AFieldOfInstancesIsVisitedAlongAPath) {
    // 64 x 64 sticks 3 apart, each turned its own way: a ray down onto one of them visits a path
    // of the 8-wide top level (about log8(4096) = 4 levels), not the field; a median-split binary
    // tree of one instance per leaf visits at least its 12 levels.
    std::vector<Instance> field;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j)
            field.push_back({0, turned(0.1f * float(i * 64 + j), 3.0f * float(i), 3.0f * float(j))});
    const InstancedAccel accel(stick(), field, "bvh8");
    EXPECT_LE(accel.top().tree().max_depth, 8u);
    EXPECT_LT(accel.top().node_count(), field.size());  // 8-wide: under one node per instance
    RayCounters c;
    const Affine& t = field[33 * 64 + 17].transform;
    const Vec3 on = t.point({0.5f, 0.0f, 0.0f});
    const Hit hit = accel.intersect(Ray{{on.x, 2.0f, on.z}, 0.0f, {0.0f, -1.0f, 0.0f}}, c);
    ASSERT_TRUE(hit.found());
    EXPECT_EQ(accel.locate(hit.prim).instance, 33u * 64 + 17);
    EXPECT_LT(c.nodes, 24u);
}
