// HitColumns (query/hit_columns.h), the columns cast_rays answers in: the four-row SIMD stores
// write what the scalar put() writes, bit for bit, streamed or not, for hits, misses and rows
// without a ray, and a scene without a normal table takes Scene::normal at the hit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <new>
#include <random>
#include <vector>

#include "thicket/query/hit_columns.h"
#include "thicket/accel/registry.h"
#include "thicket/scene/scene.h"

namespace thicket::testing::hit_columns_test {
namespace {

/// 16-byte aligned storage: the four-row streamed stores require it (as stream_when_large() checks).
template <class T>
struct Aligned16 {
    using value_type = T;
    Aligned16() = default;
    template <class U>
    Aligned16(const Aligned16<U>&) {}
    T* allocate(size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(16))); }
    void deallocate(T* p, size_t) { ::operator delete(p, std::align_val_t(16)); }
    bool operator==(const Aligned16&) const { return true; }
};
template <class T>
using Column = std::vector<T, Aligned16<T>>;

/// Columns for `rows` rows, 16-byte aligned (what streaming needs), filled with a pattern no
/// answer writes, so that a row left unwritten shows.
struct Buffers {
    explicit Buffers(size_t rows) : t(rows + 4), geom(rows + 4), prim(rows + 4), uv(2 * rows + 4), nrm(3 * rows + 4) {
        for (auto* v : {&t, &uv, &nrm}) std::fill(v->begin(), v->end(), -7.0f);
        for (auto* v : {&geom, &prim}) std::fill(v->begin(), v->end(), 0x5A5A5A5Au);
    }
    Column<float> t;
    Column<uint32_t> geom, prim;
    Column<float> uv, nrm;
    HitColumns columns(const Scene& scene, bool stream) {
        HitColumns c{t.data(), geom.data(), prim.data(), uv.data(), nrm.data(), &scene};
        c.stream = stream;
        return c;
    }
    bool operator==(const Buffers& o) const {
        return std::memcmp(t.data(), o.t.data(), t.size() * 4) == 0 && geom == o.geom && prim == o.prim &&
               std::memcmp(uv.data(), o.uv.data(), uv.size() * 4) == 0 &&
               std::memcmp(nrm.data(), o.nrm.data(), nrm.size() * 4) == 0;
    }
};

Scene random_triangles(size_t count) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    TriangleMesh mesh;
    for (size_t i = 0; i < 3 * count; ++i) {
        mesh.positions.push_back({u(rng), u(rng), u(rng)});
        mesh.indices.push_back(uint32_t(i));
    }
    Scene scene;
    scene.name = "random triangles";
    scene.add_mesh(mesh);
    return scene;
}

/// Rows of rays from a sphere around the scene towards points in it: some hit, some miss; when
/// `holes`, every fifth row has no meaning (a NaN origin).
std::vector<float> ray_rows(size_t count, bool holes) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1.5f, 1.5f);
    std::vector<float> rows;
    for (size_t i = 0; i < count; ++i) {
        const Vec3 o{u(rng), u(rng), 3.0f}, target{u(rng), u(rng), 0.0f};
        const Vec3 d = target - o;
        rows.insert(rows.end(), {holes && i % 5 == 3 ? NAN : o.x, o.y, o.z, d.x, d.y, d.z, 0.0f, kInfinity});
    }
    return rows;
}

TEST(HitColumns, FourRowStoresWriteWhatPutWrites) {
    const Scene scene = random_triangles(200);
    const auto accel = build_accel("bvh", scene);
    std::vector<Vec3> table(scene.mesh.triangle_count() + 2, Vec3{0, 0, 0});
    for (size_t i = 0; i < scene.mesh.triangle_count(); ++i)
        table[i] = scene.normal(Ray{}, Hit{0.0f, 0.0f, 0.0f, uint32_t(i)});
    const uint32_t miss_entry = uint32_t(table.size() - 2);
    for (const bool holes : {false, true})
        for (const bool stream : {false, true}) {
            SCOPED_TRACE(::testing::Message() << "holes " << holes << ", stream " << stream);
            const size_t n = 2 * kBatchGrain + 13;  // two whole chunks and a short one
            const std::vector<float> rows = ray_rows(n, holes);
            const RayRows in{rows.data(), n, 8};
            Buffers chunked(n), by_row(n);
            const HitColumns a = chunked.columns(scene, stream), b = by_row.columns(scene, stream);
            size_t hits = 0, misses = 0;
            for (size_t begin = 0; begin < n; begin += kBatchGrain) {
                RayChunk c;
                fill_chunk(in, begin, std::min(n, begin + kBatchGrain), c);
                std::vector<Hit> found(c.count);
                accel->intersect_chunk(c.span(), found, false);
                a.put_chunk(c, found.data(), table.data(), miss_entry);
                c.for_each_row_without_ray([&](size_t row) { b.put(row, Hit{}, Vec3{0, 0, 0}); });
                for (size_t k = 0; k < c.count; ++k) {
                    b.put(c.row(k), found[k], found[k].found() ? table[found[k].prim] : Vec3{0, 0, 0});
                    (found[k].found() ? hits : misses) += 1;
                }
            }
            EXPECT_GT(hits, 50u);
            EXPECT_GT(misses, 50u);
            EXPECT_TRUE(chunked == by_row);
            // A miss reads +inf and kNoPrim; the rows past the batch are untouched.
            for (size_t row = 0; row < n; ++row)
                if (chunked.prim[row] == kNoPrim) {
                    EXPECT_TRUE(std::isinf(chunked.t[row])) << row;
                }
            EXPECT_EQ(chunked.prim[n], 0x5A5A5A5Au);
        }
}

TEST(HitColumns, WithoutATableTheNormalIsTheScenesAtTheHit) {
    const Scene scene = random_triangles(50);
    const auto accel = build_accel("bvh", scene);
    const size_t n = 100;
    const std::vector<float> rows = ray_rows(n, false);
    Buffers out(n);
    const HitColumns columns = out.columns(scene, false);
    RayChunk c;
    fill_chunk(RayRows{rows.data(), n, 8}, 0, n, c);
    std::vector<Hit> found(c.count);
    accel->intersect_chunk(c.span(), found, false);
    columns.put_chunk(c, found.data(), nullptr, 0);
    size_t checked = 0;
    for (size_t k = 0; k < c.count; ++k) {
        if (!found[k].found()) continue;
        const Vec3 want = scene.normal(c.rays.data[k], found[k]);
        EXPECT_EQ(out.nrm[3 * k], want.x);
        EXPECT_EQ(out.nrm[3 * k + 2], want.z);
        EXPECT_EQ(out.t[k], found[k].t);
        ++checked;
    }
    EXPECT_GT(checked, 10u);
}

}  // namespace
}  // namespace thicket::testing::hit_columns_test
