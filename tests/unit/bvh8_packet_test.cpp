// bvh8's packet path (coherent batches, 16 rays through the tree together) answers what the
// single-ray kernels answer, ray for ray, under every ISA this CPU runs: camera rays in 4x4 tiles
// (the case it is for), partial and mixed packets, per-ray intervals, and scenes whose rays fall
// back to single-ray traversal. The conformance suite checks the batch path against brute force on
// every scene as well; this pins it to the single-ray kernels bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "support/probe.h"
#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/bvh8/bvh8.h"
#include "thicket/bvh8/isa.h"
#include "thicket/bvh8/packets.h"
#include "thicket/core/traversal_record.h"
#include "thicket/core/error.h"
#include "thicket/render/camera.h"
#include "thicket/scene/scene.h"

namespace thicket::bvh8_packet_test {
namespace {

/// A camera's rays for a width x height image, 4x4 tiles of pixels one after the other (as
/// `thicket render` batches them).
std::vector<Ray> tiled_camera_rays(const Camera& camera, int width, int height) {
    std::vector<Ray> rays;
    for (int by = 0; by < height; by += 4)
        for (int bx = 0; bx < width; bx += 4)
            for (int y = by; y < std::min(height, by + 4); ++y)
                for (int x = bx; x < std::min(width, bx + 4); ++x)
                    rays.push_back(camera.generate(float(x) + 0.5f, float(y) + 0.5f, width, height));
    return rays;
}

/// The single-ray answers and both batch paths agree: the same t bitwise, and the same primitive
/// unless another one is hit at that very t (packets visit leaves in another order).
void expect_batch_is_single_ray(const Accel& accel, const std::vector<Ray>& rays, const std::string& what) {
    std::vector<Hit> coherent(rays.size()), plain(rays.size());
    BatchOptions hint;
    hint.coherent = true;
    accel.intersect(rays, coherent, hint);
    accel.intersect(rays, plain);
    size_t hits = 0, bad = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit single = accel.intersect(rays[i]);
        hits += single.found();
        const bool same = testing::identical_hits(coherent[i], single) ||
                          (coherent[i].found() && single.found() && coherent[i].t == single.t);
        if ((!same || !testing::identical_hits(plain[i], single)) && bad++ < 3)
            ADD_FAILURE() << what << " " << accel.spec() << " ray " << i << ": batch prim " << coherent[i].prim
                          << " t " << coherent[i].t << ", single-ray prim " << single.prim << " t " << single.t;
    }
    EXPECT_EQ(bad, 0u) << what << " " << accel.spec();
    EXPECT_GT(hits, rays.size() / 10) << what << ": the rays must hit something to test anything";
}

/// The rays a bvh8's packet kernels have answered (stats()' "packet rays").
uint64_t packet_rays(const Accel& accel) {
    for (const auto& [key, value] : accel.stats().extra)
        if (key == "packet rays") return std::stoull(value);
    ADD_FAILURE() << accel.spec() << " reports no packet rays";
    return 0;
}

std::vector<std::string> every_isa(const std::string& options) {
    std::vector<std::string> specs;
    for (Isa isa : cpu_isas())
        specs.push_back("bvh8:isa=" + std::string(isa_name(isa)) + (options.empty() ? "" : "," + options));
    return specs;
}

/// The levels with a packet kernel (docs/bvh8.md): SSE and AVX-512. AVX2's 16-ray packets spill
/// (lanes_avx2.h) and the scalar reference traces each ray alone.
bool traces_packets(const std::string& spec) {
    return spec.find("isa=sse") != std::string::npos || spec.find("isa=avx512") != std::string::npos;
}

TEST(Bvh8Packets, OnlyLevelsWithAPacketKernelSayTheyHaveOne) {
    for (Isa isa : cpu_isas())
        EXPECT_EQ(bvh8::kernels_for(isa).packets, traces_packets(std::string("isa=") + isa_name(isa)))
            << isa_name(isa);
}

TEST(Bvh8Packets, CameraTilesAnswerAsSingleRays) {
    const Scene scene = load_scene("cornell");
    const Aabb b = scene.bounds();
    // Inside the box looking at a corner: every ray has the same direction signs, so every tile is
    // a full packet; and from the front, where tiles straddle the image's axes and fall back.
    const Camera corner(b.center(), b.max, {0, 1, 0}, 50.0f);
    const Camera front(b.center() + Vec3(0, 0, 2.5f * b.extent().z), b.center(), {0, 1, 0}, 40.0f);
    for (const char* isect : {"moller", "watertight"})
        for (const std::string& spec : every_isa(std::string("isect=") + isect)) {
            const auto accel = build_accel(spec, scene);
            expect_batch_is_single_ray(*accel, tiled_camera_rays(corner, 64, 48), "corner view");
            // Nearly every corner tile shares one octant (a few hold a zero direction component):
            // the packet kernel answered nearly all of them.
            // A level without a packet kernel counts none: it traced every ray alone.
            const uint64_t corner_packets = packet_rays(*accel);
            expect_batch_is_single_ray(*accel, tiled_camera_rays(front, 67, 45), "front view");
            const uint64_t front_packets = packet_rays(*accel) - corner_packets;
            if (!traces_packets(spec)) {
                EXPECT_EQ(corner_packets + front_packets, 0u) << spec;
                continue;
            }
            EXPECT_GE(corner_packets, 64u * 48u * 9 / 10) << spec;
            EXPECT_GT(front_packets, 0u) << spec << ": most front tiles are packets too";
            EXPECT_LT(front_packets, 67u * 45u) << spec << ": tiles on the image's axes fall back";
        }
}

TEST(Bvh8Packets, PerRayIntervalsAndPartialPacketsAreKept) {
    const Scene scene = load_scene("cornell");
    const Aabb b = scene.bounds();
    const Camera corner(b.center(), b.max, {0, 1, 0}, 50.0f);
    std::vector<Ray> rays = tiled_camera_rays(corner, 32, 32);
    // Each ray gets its own window: some stop short of their hit, some start beyond it.
    const std::vector<Hit> full = [&] {
        std::vector<Hit> h(rays.size());
        build_accel("bvh8", scene)->intersect(rays, h);
        return h;
    }();
    for (size_t i = 0; i < rays.size(); ++i) {
        if (!full[i].found()) continue;
        switch ((i + 2) % 5) {  // ray 0 keeps its hit: the 1-ray batch must hit
        case 0: rays[i].tmax = full[i].t * 0.5f; break;
        case 1: rays[i].tmin = full[i].t * 1.001f; break;
        case 2: rays[i].tmin = full[i].t * 0.9f, rays[i].tmax = full[i].t * 1.1f; break;
        default: break;
        }
    }
    for (const std::string& spec : every_isa("")) {
        const auto accel = build_accel(spec, scene);
        for (size_t count : {size_t(1), size_t(5), size_t(15), size_t(17), rays.size()}) {
            const std::vector<Ray> part(rays.begin(), rays.begin() + long(count));
            expect_batch_is_single_ray(*accel, part, std::to_string(count) + " rays");
        }
    }
}

TEST(Bvh8Packets, NastyScenesAndMixedPrimitivesAnswerAsSingleRays) {
    for (const Scene& scene : testing::nasty_scenes()) {
        if (scene.mesh.triangle_count() + scene.shapes.size() < 2) continue;
        const Aabb b = scene.bounds();
        const Vec3 eye = b.min - b.extent() * 0.5f - Vec3(1e-3f);
        const Camera camera(eye, b.center(), {0, 1, 0}, 60.0f);
        const std::vector<Ray> rays = tiled_camera_rays(camera, 40, 40);
        for (const std::string& spec : every_isa("")) {
            const auto accel = build_accel(spec, scene);
            std::vector<Hit> coherent(rays.size());
            BatchOptions hint;
            hint.coherent = true;
            accel->intersect(rays, coherent, hint);
            for (size_t i = 0; i < rays.size(); ++i) {
                const Hit single = accel->intersect(rays[i]);
                ASSERT_TRUE(testing::identical_hits(coherent[i], single) || coherent[i].t == single.t)
                    << scene.name << " " << spec << " ray " << i;
            }
        }
    }
}

TEST(Bvh8Packets, PacketsOffIsTheSameAnswer) {
    const Scene scene = load_scene("cornell");
    const Aabb b = scene.bounds();
    const std::vector<Ray> rays = tiled_camera_rays(Camera(b.center(), b.max, {0, 1, 0}, 50.0f), 48, 48);
    for (const std::string& spec : every_isa("")) {
        const auto on = build_accel(spec, scene), off = build_accel(spec + ",packets=off", scene);
        std::vector<Hit> a(rays.size()), c(rays.size());
        BatchOptions hint;
        hint.coherent = true;
        on->intersect(rays, a, hint);
        off->intersect(rays, c, hint);
        for (size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(a[i].t, c[i].t) << spec << " ray " << i;
        // The comparison means something only if the packets ran, and only where they were asked
        // for: every ray on a level with a packet kernel, none on the others.
        const uint64_t packets = traces_packets(spec) ? rays.size() : 0;
        EXPECT_EQ(packet_rays(*on), packets) << spec;
        EXPECT_EQ(packet_rays(*off), 0u) << spec;
        on->intersect(rays, a);  // not marked coherent: ray by ray
        EXPECT_EQ(packet_rays(*on), packets) << spec;
    }
}

/// `layers` bumpy height fields of 2 n^2 triangles each over [0, n]^2, 3 apart in z: a tree deep
/// enough for pruning to show, and layers below the first hit that a ray must drop unvisited.
Scene height_fields(int n, int layers) {
    Scene scene;
    for (int l = 0; l < layers; ++l) {
        const uint32_t base = uint32_t(scene.mesh.positions.size());
        for (int y = 0; y <= n; ++y)
            for (int x = 0; x <= n; ++x)
                scene.mesh.positions.push_back(Vec3(float(x), float(y),
                                                    3.0f * float(l) + 2.0f * std::sin(0.37f * float(x + 7 * l)) *
                                                                          std::cos(0.29f * float(y))));
        const auto at = [n, base](int x, int y) { return base + uint32_t(y * (n + 1) + x); };
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                scene.mesh.indices.insert(scene.mesh.indices.end(), {at(x, y), at(x + 1, y), at(x + 1, y + 1),
                                                                     at(x, y), at(x + 1, y + 1), at(x, y + 1)});
    }
    return scene;
}

/// What one packet's rays do alone: the nodes each visits (entered and not dropped: the
/// recording traversal's steps), their union over the packet, and the counting traversal's sums.
struct AloneCounts {
    uint64_t nodes = 0, prims = 0, union_nodes = 0;
};
AloneCounts alone(const Accel& accel, const Ray* rays, uint32_t count, const Hit* packet_hits) {
    AloneCounts a;
    std::set<uint32_t> visited;
    for (uint32_t k = 0; k < count; ++k) {
        TraversalRecorder recorder;
        const Hit single = accel.intersect(rays[k], recorder);
        EXPECT_EQ(packet_hits[k].t, single.t) << "ray " << k;
        std::set<uint32_t> mine, dropped;
        for (const TraversalStep& s : recorder.steps) {
            if (s.kind == TraversalStep::Kind::Enter) mine.insert(s.id);
            if (s.kind == TraversalStep::Kind::Skip) dropped.insert(s.id);
        }
        for (uint32_t id : mine)
            if (!dropped.count(id)) visited.insert(id);
        RayCounters c;
        accel.intersect(rays[k], c);
        EXPECT_EQ(c.nodes, recorder.nodes) << "ray " << k << ": recording visits what counting visits";
        a.nodes += c.nodes, a.prims += c.prims;
    }
    a.union_nodes = visited.size();
    return a;
}

// Packets are a speed feature: a packet kernel that tests every child, keeps boxes beyond every
// ray's hit or sends rays into leaves they do not enter answers the same and only runs slower, so
// answers cannot show it (issue 45). Counted on camera tiles over stacked height fields (layers
// below the first hit are dropped unvisited), in two views:
// - narrow (12 degrees; rays of a tile stay together): the packet shares the node tests (its
//   visits and its rays' own are at most half the single rays'), visits no more nodes than the
//   union of what its rays visit alone (measured 2,202 against 2,264; a packet that keeps boxes
//   beyond every ray's hit, planted: 2,800), and its rays test at most 6% more primitives than
//   alone (leaves in the packet's order: measured +4.7%; rays sent into leaves beyond their own
//   hit, planted: +9.1%);
// - wide (50 degrees; tiles split early, rays finish subtrees alone): the packet's own visits are
//   at most 0.65 of that union (measured 0.618; a packet that visits children none of its rays
//   enters, planted: 0.669). Bounds measured on this deterministic scene and tree: a builder
//   change that moves them must re-measure the planted kernels too.
TEST(Bvh8Packets, PacketsShareTheNodeTestsAndPruneAsTheirRaysDoAlone) {
    const Scene scene = height_fields(64, 4);
    const Aabb b = scene.bounds();
    const Vec3 e = b.extent();
    const Vec3 eye(b.center().x, b.min.y - 0.3f * e.y, b.max.z + 0.4f * e.x);
    for (const float fov : {12.0f, 50.0f}) {
        const std::vector<Ray> rays = tiled_camera_rays(Camera(eye, b.center(), {0, 0, 1}, fov), 64, 48);
        for (const std::string& spec : every_isa("")) {
            SCOPED_TRACE(spec + ", fov " + std::to_string(fov));
            const auto accel = build_accel(spec, scene);
            const auto& bvh = dynamic_cast<const Bvh8<Triangles<>>&>(*accel);
            bvh8::PacketCounters packet;
            AloneCounts single;
            size_t packets = 0;
            for (size_t begin = 0; begin + bvh8::kPacketSize <= rays.size(); begin += bvh8::kPacketSize) {
                if (!bvh8::packet_eligible(&rays[begin], bvh8::kPacketSize)) continue;
                Hit hits[bvh8::kPacketSize];
                bvh.kernels().packet_closest_counting[Bvh8<Triangles<>>::kLeafKind](
                    bvh.trace_context(), &rays[begin], bvh8::kPacketSize, hits, &packet);
                const AloneCounts a = alone(*accel, &rays[begin], bvh8::kPacketSize, hits);
                single.nodes += a.nodes, single.prims += a.prims, single.union_nodes += a.union_nodes;
                ++packets;
            }
            ASSERT_GT(packets, rays.size() / bvh8::kPacketSize * 9 / 10) << "nearly every tile is a packet";
            if (!traces_packets(spec)) {  // no packet kernel: every ray alone, as counted alone
                EXPECT_EQ(packet.packet_nodes, 0u);
                EXPECT_EQ(packet.ray_nodes, single.nodes);
                EXPECT_EQ(packet.prims, single.prims);
                continue;
            }
            if (fov < 20.0f) {
                EXPECT_LE(packet.packet_nodes + packet.ray_nodes, single.nodes / 2) << "the node tests are shared";
                EXPECT_LE(packet.packet_nodes, single.union_nodes) << "the packet visits what its rays visit";
                EXPECT_LE(double(packet.prims), 1.06 * double(single.prims)) << "its rays test what they test alone";
            } else {
                EXPECT_LE(double(packet.packet_nodes), 0.65 * double(single.union_nodes))
                    << "the packet visits no child none of its rays enters";
            }
        }
    }
}

TEST(AccelBatch, SpansOfDifferentSizesAreAnError) {
    const auto accel = build_accel("bvh", load_scene("cornell"));
    std::vector<Ray> rays(3);
    std::vector<Hit> hits(2);
    std::vector<uint8_t> flags(4);
    EXPECT_THROW(accel->intersect(rays, hits), Error);
    EXPECT_THROW(accel->occluded(rays, flags), Error);
}

}  // namespace
}  // namespace thicket::bvh8_packet_test
