#include "thicket/query/hit_columns.h"

#include <cstring>

#include "thicket/scene/scene.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace thicket {

namespace {

/// The geometry id of a one-geometry scene's hits: what put4 writes from the miss mask alone.
constexpr uint32_t kOnlyGeometry = 0;

template <class T>
void store(bool stream, T* p, T v) {
#if defined(__SSE2__)
    if (stream) {
        int bits;
        static_assert(sizeof bits == sizeof v);
        std::memcpy(&bits, &v, sizeof bits);
        _mm_stream_si32(reinterpret_cast<int*>(p), bits);
        return;
    }
#endif
    *p = v;
}

#if defined(__SSE2__)
void store4(bool stream, float* p, __m128 v) {
    if (stream)
        _mm_stream_ps(p, v);
    else
        _mm_storeu_ps(p, v);
}

/// Rows row .. row + 3 (row a multiple of 4) answer hits[0 .. 4), as put() would with the normals
/// of `table` (a miss reads its zero entry at `miss_entry`), for a scene of one geometry. Four
/// rows at once take a third of the instructions of four put() calls.
void put4(const HitColumns& o, size_t row, const Hit* hits, const Vec3* table, uint32_t miss_entry) {
    static_assert(kOnlyGeometry == 0 && kNoPrim == 0xFFFFFFFFu, "a geometry id is the miss mask");
    __m128 ht = _mm_loadu_ps(&hits[0].t), hu = _mm_loadu_ps(&hits[1].t);
    __m128 hv = _mm_loadu_ps(&hits[2].t), hp = _mm_loadu_ps(&hits[3].t);
    _MM_TRANSPOSE4_PS(ht, hu, hv, hp);  // rows of t, u, v and the primitives' bits
    const __m128 miss = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_castps_si128(hp), _mm_set1_epi32(-1)));
    store4(o.stream, o.t + row, _mm_or_ps(_mm_andnot_ps(miss, ht), _mm_and_ps(miss, _mm_set1_ps(kInfinity))));
    store4(o.stream, reinterpret_cast<float*>(o.geom + row), miss);
    store4(o.stream, reinterpret_cast<float*>(o.prim + row), hp);
    const __m128 u = _mm_andnot_ps(miss, hu), v = _mm_andnot_ps(miss, hv);
    store4(o.stream, o.uv + 2 * row, _mm_unpacklo_ps(u, v));
    store4(o.stream, o.uv + 2 * row + 4, _mm_unpackhi_ps(u, v));
    // Each normal read as four floats (x y z and the next entry's x), then packed into three rows
    // of four: x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3.
    __m128 n[4];
    for (int i = 0; i < 4; ++i) n[i] = _mm_loadu_ps(&table[hits[i].found() ? hits[i].prim : miss_entry].x);
    const __m128 z0x1 = _mm_shuffle_ps(n[0], n[1], _MM_SHUFFLE(0, 0, 2, 2));  // z0 z0 x1 x1
    const __m128 z2x3 = _mm_shuffle_ps(n[2], n[3], _MM_SHUFFLE(0, 0, 2, 2));  // z2 z2 x3 x3
    store4(o.stream, o.nrm + 3 * row, _mm_shuffle_ps(n[0], z0x1, _MM_SHUFFLE(2, 0, 1, 0)));
    store4(o.stream, o.nrm + 3 * row + 4, _mm_shuffle_ps(n[1], n[2], _MM_SHUFFLE(1, 0, 2, 1)));
    store4(o.stream, o.nrm + 3 * row + 8, _mm_shuffle_ps(z2x3, n[3], _MM_SHUFFLE(2, 1, 2, 0)));
}
#endif

}  // namespace

void HitColumns::stream_when_large(size_t rows) {
    const auto aligned = [](const void* p) { return reinterpret_cast<uintptr_t>(p) % 16 == 0; };
    stream = rows * sizeof(float) >= kStreamBytes && aligned(t) && aligned(geom) && aligned(prim) && aligned(uv) &&
             aligned(nrm);
}

void HitColumns::put(size_t row, const Hit& hit, const Vec3& n) const {
    const bool found = hit.found();
    store(stream, t + row, found ? hit.t : kInfinity);
    store(stream, geom + row, scene->geometry_of(hit.prim));  // a miss's kNoPrim stays kNoPrim
    store(stream, prim + row, hit.prim);
    store(stream, uv + 2 * row, found ? hit.u : 0.0f);
    store(stream, uv + 2 * row + 1, found ? hit.v : 0.0f);
    store(stream, nrm + 3 * row, found ? n.x : 0.0f);
    store(stream, nrm + 3 * row + 1, found ? n.y : 0.0f);
    store(stream, nrm + 3 * row + 2, found ? n.z : 0.0f);
}

void HitColumns::put_chunk(const RayChunk& c, const Hit* hits, const Vec3* normals, uint32_t miss_entry) const {
    if (c.sorted && stream) {
        // A reordered block's rows are scattered over its range: streamed, each 4-byte store would
        // send a partial line to memory; through the cache the rows of a line merge before they leave.
        HitColumns cached = *this;
        cached.stream = false;
        return cached.put_chunk(c, hits, normals, miss_entry);
    }
    if (normals)  // the table is cold (tracing evicts it): its misses overlap when asked for first
        for (size_t k = 0; k < c.count; ++k)
            if (hits[k].found()) __builtin_prefetch(normals + hits[k].prim);
    size_t k = 0;
#if defined(__SSE2__)
    // Nearly every chunk: c.begin and k are multiples of 4.
    if (c.contiguous() && normals && scene->geometry_count() <= 1)
        for (; k + 4 <= c.count; k += 4) put4(*this, c.begin + k, hits + k, normals, miss_entry);
#endif
    c.for_each_row_without_ray([&](size_t row) { put(row, Hit{}, Vec3{0, 0, 0}); });  // misses
    for (; k < c.count; ++k) {
        const Hit& hit = hits[k];
        const Vec3 n = !hit.found() ? Vec3{0, 0, 0} : normals ? normals[hit.prim] : scene->normal(c.rays.data[k], hit);
        put(c.row(k), hit, n);
    }
#if defined(__SSE2__)
    // Non-temporal stores are weakly ordered: fenced, this thread's streamed answers are seen
    // before its later stores (the end of the parallel loop that hands the columns back among them).
    if (stream) _mm_sfence();
#endif
}

}  // namespace thicket
