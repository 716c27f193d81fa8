// Micro-benchmarks of the kernels every query spends its time in. Inputs are generated with the
// bench's fixed-seed generator, so runs compare like with like; each benchmark cycles through a
// few thousand inputs so that branch predictors cannot learn one answer.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/bench/ray_sets.h"
#include "thicket/bench/rng.h"
#include "thicket/bvh/bvh.h"
#include "thicket/bvh8/bvh8.h"
#include "thicket/core/ray_box.h"
#include "thicket/core/triangle.h"
#include "thicket/prims/triangles.h"

using namespace thicket;

namespace {

constexpr size_t kInputs = 4096;  // a power of two: inputs are picked with i & (kInputs - 1)

Vec3 random_point(Pcg32& rng) { return {rng.next_signed(), rng.next_signed(), rng.next_signed()}; }

// Rays from a sphere of radius 3 towards random points of the unit cube: most of them pass near
// the boxes and triangles below, about half hit.
std::vector<Ray> cube_rays(uint64_t seed) {
    Pcg32 rng(seed);
    std::vector<Ray> rays(kInputs);
    for (Ray& r : rays) {
        r.org = sample_unit_sphere(rng) * 3.0f;
        r.dir = normalize(random_point(rng) - r.org);
    }
    return rays;
}

void BM_RayBoxEntry(benchmark::State& state) {
    Pcg32 rng(1);
    std::vector<Aabb> boxes(kInputs);
    for (Aabb& b : boxes) {
        b.grow(random_point(rng));
        b.grow(random_point(rng));
    }
    std::vector<RayBoxQuery> queries;
    const std::vector<Ray> rays = cube_rays(2);
    for (const Ray& r : rays) queries.emplace_back(r);
    size_t i = 0;
    for (auto _ : state) {
        const size_t k = i++ & (kInputs - 1);
        benchmark::DoNotOptimize(ray_box_entry(queries[k], boxes[k], 0.0f, kInfinity));
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_RayBoxEntry);

template <TriangleTest Test>
void BM_RayTriangle(benchmark::State& state) {
    Pcg32 rng(3);
    std::vector<Vec3> v(3 * kInputs);
    for (size_t t = 0; t < kInputs; ++t) {
        const Vec3 c = random_point(rng) * 0.5f;  // small triangles around random centres
        for (int k = 0; k < 3; ++k) v[3 * t + k] = c + random_point(rng) * 0.5f;
    }
    const std::vector<Ray> rays = cube_rays(4);
    size_t i = 0;
    for (auto _ : state) {
        const size_t k = i++ & (kInputs - 1);
        TriangleHit hit;
        const bool found = intersect_triangle<Test>(v[3 * k], v[3 * k + 1], v[3 * k + 2], rays[k], kInfinity, hit);
        benchmark::DoNotOptimize(found);
        benchmark::DoNotOptimize(hit);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_RayTriangle<TriangleTest::Moller>)->Name("BM_RayTriangle/moller");
BENCHMARK(BM_RayTriangle<TriangleTest::Watertight>)->Name("BM_RayTriangle/watertight");

// A small closed scene: a latitude-longitude sphere of 64 x 32 quads (4,096 triangles) with a
// floor, so that primary rays hit, shadow rays get blocked, and the BVH has some depth.
Scene small_scene() {
    Scene s;
    s.name = "micro sphere";
    constexpr int kLon = 64, kLat = 32;
    constexpr float kPi = 3.14159265f;
    for (int j = 0; j <= kLat; ++j) {
        for (int i = 0; i < kLon; ++i) {
            const float theta = kPi * float(j) / kLat, phi = 2.0f * kPi * float(i) / kLon;
            const float r = std::sin(theta);
            s.mesh.positions.push_back({r * std::cos(phi), std::cos(theta), r * std::sin(phi)});
        }
    }
    for (int j = 0; j < kLat; ++j) {
        for (int i = 0; i < kLon; ++i) {
            const uint32_t a = uint32_t(j * kLon + i), b = uint32_t(j * kLon + (i + 1) % kLon);
            const uint32_t c = a + kLon, d = b + kLon;
            s.mesh.indices.insert(s.mesh.indices.end(), {a, c, b, b, c, d});
        }
    }
    const uint32_t base = uint32_t(s.mesh.positions.size());
    for (Vec3 p : {Vec3{-3, -1, -3}, Vec3{3, -1, -3}, Vec3{3, -1, 3}, Vec3{-3, -1, 3}}) s.mesh.positions.push_back(p);
    s.mesh.indices.insert(s.mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
    return s;
}

struct SmallSceneFixture {
    Scene scene = small_scene();
    Bvh<Triangles<TriangleTest::Moller>> bvh{Triangles<TriangleTest::Moller>(scene.mesh), BvhBuildOptions{}};
    std::vector<RaySet> sets;

    SmallSceneFixture() {
        RaySetOptions options;
        options.width = 64;
        options.height = 64;
        const std::vector<std::string> names{"primary", "shadow"};
        sets = generate_ray_sets(scene, bvh, names, options, 1);
    }
    static const SmallSceneFixture& get() {
        static const SmallSceneFixture fixture;
        return fixture;
    }
};

// One visit of an interior node as the ordered traversal makes it: both children's boxes tested
// and the nearer one chosen.
void BM_BvhNodeVisit(benchmark::State& state) {
    const auto& f = SmallSceneFixture::get();
    const BvhData& data = f.bvh.data();
    std::vector<uint32_t> interior;
    for (uint32_t n = 0; n < data.nodes_used; ++n)
        if (n != 1 && !data.nodes[n].is_leaf()) interior.push_back(n);
    std::vector<uint32_t> visits(kInputs);  // interior nodes cycled, so that a mask picks one
    for (size_t k = 0; k < kInputs; ++k) visits[k] = interior[k % interior.size()];
    const std::vector<Ray> rays = cube_rays(5);
    std::vector<RayBoxQuery> queries;
    for (const Ray& r : rays) queries.emplace_back(r);
    size_t i = 0;
    for (auto _ : state) {
        const size_t k = i++ & (kInputs - 1);
        const BvhNode& node = data.nodes[visits[k]];
        const BvhNode& left = data.nodes[node.leftFirst];
        const BvhNode& right = data.nodes[node.leftFirst + 1];
        const RayBoxQuery& q = queries[(k * 7) & (kInputs - 1)];  // rays and nodes paired differently
        const float tl = ray_box_entry(q, left.aabbMin, left.aabbMax, 0.0f, kInfinity);
        const float tr = ray_box_entry(q, right.aabbMin, right.aabbMax, 0.0f, kInfinity);
        benchmark::DoNotOptimize(tr < tl ? node.leftFirst + 1 : node.leftFirst);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_BvhNodeVisit);

// A whole closest-hit query, called directly (no virtual call) and through the Accel interface.
void BM_BvhClosestHit(benchmark::State& state) {
    const auto& f = SmallSceneFixture::get();
    const std::vector<Ray>& rays = f.sets[0].rays;
    size_t i = 0;
    for (auto _ : state) {
        NoCounters none;
        benchmark::DoNotOptimize(f.bvh.closest(rays[i++ % rays.size()], none));
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_BvhClosestHit);

void BM_AccelClosestHit(benchmark::State& state) {
    const auto& f = SmallSceneFixture::get();
    const Accel& accel = f.bvh;
    const std::vector<Ray>& rays = f.sets[0].rays;
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(accel.intersect(rays[i++ % rays.size()]));
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_AccelClosestHit);

void BM_BvhAnyHitShadow(benchmark::State& state) {
    const auto& f = SmallSceneFixture::get();
    const std::vector<Ray>& rays = f.sets[1].rays;
    size_t i = 0;
    for (auto _ : state) {
        NoCounters none;
        benchmark::DoNotOptimize(f.bvh.any(rays[i++ % rays.size()], none));
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_BvhAnyHitShadow);

// ---- bvh8: its node and leaf kernels under each ISA, and whole queries ---------------------
// The argument is the ISA level (0 scalar, 1 sse, 2 avx2, 3 avx512); levels the CPU lacks skip.

bool use_isa(benchmark::State& state, Isa& isa) {
    isa = Isa(state.range(0));
    if (isa > cpu_best_isa()) {
        state.SkipWithError("the CPU lacks this ISA");
        return false;
    }
    state.SetLabel(isa_name(isa));
    return true;
}

// 8-wide nodes: 8 slab tests each, the mask of children entered and their entry distances; one
// ray tests 64 nodes, so that the per-ray setup (3 divisions, the octant) is amortized as in a
// traversal. Items are nodes.
AlignedVector<bvh8::Node, 64> random_nodes() {
    Pcg32 rng(6);
    AlignedVector<bvh8::Node, 64> nodes(256);
    for (bvh8::Node& n : nodes) {
        n.valid = 0xff;
        for (int lane = 0; lane < 8; ++lane) {
            Aabb b;
            b.grow(random_point(rng));
            b.grow(random_point(rng));
            for (int a = 0; a < 3; ++a) n.box[a][0][lane] = b.min[a], n.box[a][1][lane] = b.max[a];
        }
    }
    return nodes;
}

void BM_Bvh8NodeTest(benchmark::State& state) {
    Isa isa;
    if (!use_isa(state, isa)) return;
    const auto test = bvh8::kernels_for(isa).node_test;
    const AlignedVector<bvh8::Node, 64> nodes = random_nodes();
    const std::vector<Ray> rays = cube_rays(7);
    size_t i = 0;
    alignas(32) float dist[8];
    uint32_t any = 0;
    for (auto _ : state) {
        const size_t k = i++ & (kInputs - 1);
        benchmark::DoNotOptimize(test(&nodes[(k * 64) & 255], 64, rays[k], kInfinity, dist, &any));
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * 64);
}
BENCHMARK(BM_Bvh8NodeTest)->DenseRange(0, 3);

// The same nodes and rays through the traversal's slab test: one multiply-add per plane against
// the tree's plane bounds (docs/bvh8.md, "The slab test at one FMA per plane").
void BM_Bvh8NodeTestFma(benchmark::State& state) {
    Isa isa;
    if (!use_isa(state, isa)) return;
    const auto test = bvh8::kernels_for(isa).node_test_fast;
    const AlignedVector<bvh8::Node, 64> nodes = random_nodes();
    bvh8::TraceContext ctx;
    bvh8::set_plane_bounds(ctx, nodes.data(), nodes.size());
    const std::vector<Ray> rays = cube_rays(7);
    size_t i = 0;
    alignas(32) float dist[8];
    uint32_t any = 0;
    bool fma = false;
    for (auto _ : state) {
        const size_t k = i++ & (kInputs - 1);
        benchmark::DoNotOptimize(test(ctx, &nodes[(k * 64) & 255], 64, rays[k], kInfinity, dist, &any, &fma));
    }
    if (!fma) state.SkipWithError("the rays did not take the FMA path");
    state.SetItemsProcessed(int64_t(state.iterations()) * 64);
}
BENCHMARK(BM_Bvh8NodeTestFma)->DenseRange(0, 3);

// One 4-triangle block: Moller-Trumbore on 4 lanes, bitwise the scalar test's results.
void BM_Bvh8BlockTest(benchmark::State& state) {
    Isa isa;
    if (!use_isa(state, isa)) return;
    const auto test = bvh8::kernels_for(isa).block_test;
    Pcg32 rng(8);
    std::vector<bvh8::Tri4> blocks(256);
    for (bvh8::Tri4& b : blocks)
        for (int lane = 0; lane < 4; ++lane) {
            b.id[lane] = uint32_t(lane);
            for (int k = 0; k < 3; ++k) {
                const Vec3 p = random_point(rng);
                for (int a = 0; a < 3; ++a) b.v[k][a][lane] = p[a];
            }
        }
    const std::vector<Ray> rays = cube_rays(9);
    size_t i = 0;
    float t[4];
    for (auto _ : state) {
        const size_t k = i++ & (kInputs - 1);
        benchmark::DoNotOptimize(test(blocks[k & 255], rays[k], kInfinity, t));
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_Bvh8BlockTest)->DenseRange(0, 3);

// Whole queries on the small scene, through the Accel interface as the bench calls them.
void BM_Bvh8ClosestHit(benchmark::State& state) {
    Isa isa;
    if (!use_isa(state, isa)) return;
    const auto& f = SmallSceneFixture::get();
    const auto accel = build_accel(std::string("bvh8:isa=") + isa_name(isa), f.scene);
    const std::vector<Ray>& rays = f.sets[0].rays;
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(accel->intersect(rays[i++ % rays.size()]));
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_Bvh8ClosestHit)->DenseRange(0, 3);

void BM_Bvh8AnyHitShadow(benchmark::State& state) {
    Isa isa;
    if (!use_isa(state, isa)) return;
    const auto& f = SmallSceneFixture::get();
    const auto accel = build_accel(std::string("bvh8:isa=") + isa_name(isa), f.scene);
    const std::vector<Ray>& rays = f.sets[1].rays;
    size_t i = 0;
    for (auto _ : state) benchmark::DoNotOptimize(accel->occluded(rays[i++ % rays.size()]));
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_Bvh8AnyHitShadow)->DenseRange(0, 3);

}  // namespace
