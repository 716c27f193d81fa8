// bvh8 lists every crossing in one traversal (all_entry) and merges hits into crossings by the
// rule of stepping from one to the next (merge_crossings): these tests pin it to stepping and to
// brute force where the conformance suite's scenes do not reach: more hits than the stack buffer
// holds, hits at one t from several triangles, and triangles cut by spatial splits.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/bvh8/isa.h"
#include "thicket/scene/scene.h"

namespace thicket::bvh8_all_hits_test {
namespace {

/// `layers` unit squares (two triangles each) stacked along z at z = 0, 1, ..., each split along
/// its diagonal x = y.
Scene stacked_squares(int layers) {
    TriangleMesh mesh;
    for (int k = 0; k < layers; ++k) {
        const uint32_t base = uint32_t(mesh.positions.size());
        const float z = float(k);
        mesh.positions.insert(mesh.positions.end(), {{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}});
        for (uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
    }
    Scene scene;
    scene.name = "stacked-squares";
    scene.add_mesh(mesh);
    return scene;
}

/// What Accel::all_hits' default answers: closest hit, then again from just past it.
std::vector<Hit> stepping(const Accel& accel, Ray ray) {
    std::vector<Hit> out;
    for (;;) {
        const Hit hit = accel.intersect(ray);
        if (!hit.found()) return out;
        out.push_back(hit);
        const float next = next_crossing_t(hit.t);
        if (!(next <= ray.tmax) || !std::isfinite(next)) return out;
        ray.tmin = next;
    }
}

void expect_same_crossings(const std::vector<Hit>& got, const std::vector<Hit>& want, const std::string& what) {
    ASSERT_EQ(got.size(), want.size()) << what;
    for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].t, want[i].t) << what << ", crossing " << i;
}

TEST(Bvh8AllHits, MoreHitsThanTheStackBufferAreAllListedInOrder) {
    const Scene scene = stacked_squares(300);
    for (Isa isa : cpu_isas()) {
        const std::string spec = std::string("bvh8:isa=") + isa_name(isa);
        const std::unique_ptr<Accel> accel = build_accel(spec, scene);
        const std::unique_ptr<Accel> brute = build_accel("brute", scene);
        // Through the middle of one triangle of each square; then on the shared diagonal, where
        // both triangles of each square are hit at one t and make one crossing.
        for (const Vec3 org : {Vec3{0.7f, 0.2f, -1.0f}, Vec3{0.5f, 0.5f, -1.0f}}) {
            const Ray ray{org, 0.0f, {0, 0, 1}, kInfinity};
            std::vector<Hit> got;
            accel->all_hits(ray, got);
            ASSERT_EQ(got.size(), 300u) << spec;
            EXPECT_EQ(accel->count_hits(ray), 300u) << spec;
            for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].t, float(i) + 1.0f) << spec << ", crossing " << i;
            std::vector<Hit> reference;
            brute->all_hits(ray, reference);
            expect_same_crossings(got, reference, spec + " against brute force");
            expect_same_crossings(got, stepping(*accel, ray), spec + " against stepping");
            // An interval that starts and ends on a square: both ends count, as stepping does.
            const Ray part{org, 11.0f, {0, 0, 1}, 20.0f};
            EXPECT_EQ(accel->count_hits(part), 10u) << spec;
            expect_same_crossings([&] { std::vector<Hit> h; accel->all_hits(part, h); return h; }(),
                                  stepping(*accel, part), spec + " on [11, 20]");
        }
    }
}

TEST(Bvh8AllHits, TrianglesCutBySpatialSplitsCountOnce) {
    // Small triangles filling a box, crossed by 16 stacked slivers along its diagonal: a sliver's
    // box covers a whole layer of the small ones, so spatial splits cut the slivers into several
    // leaves each.
    TriangleMesh mesh;
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
            for (int l = 0; l < 12; ++l) {
                const uint32_t base = uint32_t(mesh.positions.size());
                const float x = 0.33f * float(i), y = 0.33f * float(j), z = 0.7f * float(l);
                mesh.positions.insert(mesh.positions.end(), {{x, y, z}, {x + 0.1f, y, z}, {x, y + 0.1f, z + 0.05f}});
                for (uint32_t k : {0u, 1u, 2u}) mesh.indices.push_back(base + k);
            }
    for (int k = 0; k < 16; ++k) {
        const uint32_t base = uint32_t(mesh.positions.size());
        const float z = 0.3f + 0.5f * float(k);
        mesh.positions.insert(mesh.positions.end(), {{0, 0, z}, {4, 4, z}, {4, 3.6f, z}});
        for (uint32_t i : {0u, 1u, 2u}) mesh.indices.push_back(base + i);
    }
    Scene scene;
    scene.name = "floor-and-slivers";
    scene.add_mesh(mesh);
    const std::unique_ptr<Accel> accel = build_accel("bvh8:quality=high", scene);
    const std::unique_ptr<Accel> brute = build_accel("brute", scene);
    size_t references = 0;
    for (const auto& [key, value] : accel->stats().extra)
        if (key == "references") references = std::stoul(value);
    ASSERT_GT(references, mesh.indices.size() / 3) << "no triangle was cut: this scene would not test spatial splits";
    size_t crossings = 0;
    for (int i = 0; i < 400; ++i) {
        // Down through a point of the slivers' common footprint.
        const float a = 0.05f + 0.9f * float(i) / 400.0f, b = 0.3f * float(i % 7) / 7.0f * (1.0f - a);
        const Vec3 p = Vec3{0, 0, 0} * (1.0f - a - b) + Vec3{4, 4, 0} * a + Vec3{4, 3.6f, 0} * b;
        const Ray ray{{p.x, p.y, 20.0f}, 0.0f, {0.0001f, 0.00005f, -1.0f}, kInfinity};
        std::vector<Hit> got, want;
        accel->all_hits(ray, got);
        brute->all_hits(ray, want);
        expect_same_crossings(got, want, "ray " + std::to_string(i));
        expect_same_crossings(got, stepping(*accel, ray), "ray " + std::to_string(i) + " against stepping");
        EXPECT_EQ(accel->count_hits(ray), want.size()) << "ray " << i;
        crossings += got.size();
    }
    EXPECT_GE(crossings, 400u * 16);  // every ray crosses the 16 slivers
}

}  // namespace
}  // namespace thicket::bvh8_all_hits_test
