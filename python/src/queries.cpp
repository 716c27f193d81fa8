#include "queries.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <iterator>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket::python {

namespace {

constexpr uint32_t kGeometryId = 0;  // one geometry per structure (Open3D numbers its meshes)

BatchOptions batch_options(unsigned threads, bool coherent) {
    BatchOptions o;
    o.threads = threads;
    o.coherent = coherent;
    return o;
}

/// h.triangle_normals, made on first use for a triangle scene (null for a scene with shapes,
/// whose normals depend on the hit point). Call with the GIL held; it is released while the
/// normals are computed, in parallel, with Scene::normal itself, so that they are its bits.
std::shared_ptr<const std::vector<Vec3>> triangle_normals(AccelHandle& h, unsigned threads) {
    if (h.triangle_normals || h.scene->has_shapes()) return h.triangle_normals;
    const size_t count = h.scene->mesh.triangle_count();
    // Two zero entries past the last: a miss's normal (CastOutputs::put4), and room for reading
    // any entry as four floats.
    auto normals = std::make_shared<std::vector<Vec3>>(count + 2, Vec3{0, 0, 0});
    {
        py::gil_scoped_release nogil;
        parallel_for(count, 4096, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) (*normals)[i] = h.scene->normal(Ray{}, Hit{0.0f, 0.0f, 0.0f, uint32_t(i)});
        });
    }
    if (!h.triangle_normals) h.triangle_normals = std::move(normals);
    return h.triangle_normals;
}

/// cast_rays' five arrays, as the worker threads write them: with non-temporal stores when they
/// are large (kStreamBytes says why) and 16-byte aligned, through the cache otherwise. Written
/// row by row through the cache they took ~5% of cast_rays' time on 10^6 rays (perf).
struct CastOutputs {
    float* t;
    uint32_t* geom;
    uint32_t* prim;
    float* uv;
    float* nrm;
    bool stream;

    /// Row `row` answers `hit` (a miss: t inf, ids 4294967295, zero uv and normal); n is the hit's normal.
    void put(size_t row, const Hit& hit, const Vec3& n) const {
        const bool found = hit.found();
        // A miss is +inf, not the ray's tmax (Open3D's and `thicket trace`'s convention).
        store(t + row, found ? hit.t : kInfinity);
        store(geom + row, found ? kGeometryId : kNoPrim);
        store(prim + row, hit.prim);
        store(uv + 2 * row, found ? hit.u : 0.0f);
        store(uv + 2 * row + 1, found ? hit.v : 0.0f);
        store(nrm + 3 * row, found ? n.x : 0.0f);
        store(nrm + 3 * row + 1, found ? n.y : 0.0f);
        store(nrm + 3 * row + 2, found ? n.z : 0.0f);
    }

#if defined(__SSE2__)
    /// Rows row .. row + 3 (row a multiple of 4) answer hits[0 .. 4), as put() would with the
    /// normals of `table` (triangle_normals': a miss reads its zero entry at `miss_entry`). Four
    /// rows at once take a third of the instructions of four put() calls.
    void put4(size_t row, const Hit* hits, const Vec3* table, uint32_t miss_entry) const {
        static_assert(sizeof(Hit) == 16 && offsetof(Hit, prim) == 12, "Hit is t u v prim");
        static_assert(kGeometryId == 0 && kNoPrim == 0xFFFFFFFFu, "a geometry id is the miss mask");
        __m128 ht = _mm_loadu_ps(&hits[0].t), hu = _mm_loadu_ps(&hits[1].t);
        __m128 hv = _mm_loadu_ps(&hits[2].t), hp = _mm_loadu_ps(&hits[3].t);
        _MM_TRANSPOSE4_PS(ht, hu, hv, hp);  // rows of t, u, v and the primitives' bits
        const __m128 miss = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_castps_si128(hp), _mm_set1_epi32(-1)));
        store4(t + row, _mm_or_ps(_mm_andnot_ps(miss, ht), _mm_and_ps(miss, _mm_set1_ps(kInfinity))));
        store4(reinterpret_cast<float*>(geom + row), miss);
        store4(reinterpret_cast<float*>(prim + row), hp);
        const __m128 u = _mm_andnot_ps(miss, hu), v = _mm_andnot_ps(miss, hv);
        store4(uv + 2 * row, _mm_unpacklo_ps(u, v));
        store4(uv + 2 * row + 4, _mm_unpackhi_ps(u, v));
        // Each normal read as four floats (x y z and the next entry's x), then packed into three
        // rows of four: x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3.
        __m128 n[4];
        for (int i = 0; i < 4; ++i) n[i] = _mm_loadu_ps(&table[hits[i].found() ? hits[i].prim : miss_entry].x);
        const __m128 z0x1 = _mm_shuffle_ps(n[0], n[1], _MM_SHUFFLE(0, 0, 2, 2));  // z0 z0 x1 x1
        const __m128 z2x3 = _mm_shuffle_ps(n[2], n[3], _MM_SHUFFLE(0, 0, 2, 2));  // z2 z2 x3 x3
        store4(nrm + 3 * row, _mm_shuffle_ps(n[0], z0x1, _MM_SHUFFLE(2, 0, 1, 0)));
        store4(nrm + 3 * row + 4, _mm_shuffle_ps(n[1], n[2], _MM_SHUFFLE(1, 0, 2, 1)));
        store4(nrm + 3 * row + 8, _mm_shuffle_ps(z2x3, n[3], _MM_SHUFFLE(2, 1, 2, 0)));
    }

    void store4(float* p, __m128 v) const {
        if (stream)
            _mm_stream_ps(p, v);
        else
            _mm_storeu_ps(p, v);
    }
#endif

    template <class T>
    void store(T* p, T v) const {
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
};

}  // namespace

py::dict cast_rays(AccelHandle& h, const py::handle& rays_obj, unsigned threads, bool coherent) {
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    const std::shared_ptr<const std::vector<Vec3>> normal_table = triangle_normals(h, threads);
    const Vec3* table = normal_table && normal_table->size() > 2 ? normal_table->data() : nullptr;
    const uint32_t miss_entry = normal_table ? uint32_t(normal_table->size() - 2) : 0;
    // numpy allocates without touching: the worker threads that write a chunk's answers take its
    // pages' first-touch faults, in parallel and next to the tracing.
    auto t_hit = new_array<float>(rows.lead);
    auto geometry_ids = new_array<uint32_t>(rows.lead);
    auto primitive_ids = new_array<uint32_t>(rows.lead);
    auto uvs = new_array<float>(rows.lead, {2});
    auto normals = new_array<float>(rows.lead, {3});
    // Taken with the GIL held; the arrays stay alive in this frame.
    CastOutputs o{t_hit.mutable_data(), geometry_ids.mutable_data(), primitive_ids.mutable_data(),
                    uvs.mutable_data(), normals.mutable_data(), false};
    const auto aligned = [](const void* p) { return reinterpret_cast<uintptr_t>(p) % 16 == 0; };
    o.stream = size_t(t_hit.nbytes()) >= kStreamBytes && aligned(o.t) && aligned(o.geom) && aligned(o.prim) &&
               aligned(o.uv) && aligned(o.nrm);
    {
        py::gil_scoped_release nogil;
        const BatchOptions one = chunk_options(coherent);
        for_each_ray_chunk(rows, 0.0f, kInfinity, threads, [&](const RayChunk& c) {
            Uninitialized<Hit> hits;
            h.accel->intersect({c.rays.data, c.count}, {hits.data, c.count}, one);
            if (table)  // the table is cold (tracing evicts it): its misses overlap when asked for first
                for (size_t k = 0; k < c.count; ++k)
                    if (hits.data[k].found()) __builtin_prefetch(table + hits.data[k].prim);
            size_t k = 0;
#if defined(__SSE2__)
            if (c.complete() && table)  // nearly every chunk: c.begin and k are multiples of 4
                for (; k + 4 <= c.count; k += 4) o.put4(c.begin + k, hits.data + k, table, miss_entry);
#endif
            if (!c.complete())  // rows without a ray are misses
                for (size_t row = c.begin; row < c.end; ++row) o.put(row, Hit{}, Vec3{0, 0, 0});
            for (; k < c.count; ++k) {
                const Hit& hit = hits.data[k];
                const Vec3 n = !hit.found() ? Vec3{0, 0, 0} : table ? table[hit.prim] : h.scene->normal(c.rays.data[k], hit);
                o.put(c.row(k), hit, n);
            }
            stream_fence();
        });
    }
    py::dict out;
    out["t_hit"] = t_hit;
    out["geometry_ids"] = geometry_ids;
    out["primitive_ids"] = primitive_ids;
    out["primitive_uvs"] = uvs;
    out["primitive_normals"] = normals;
    return out;
}

py::array test_occlusions(const AccelHandle& h, const py::handle& rays_obj, std::optional<float> tnear,
                          std::optional<float> tfar, unsigned threads, bool coherent) {
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    check_interval_arguments(rows, tnear, tfar);
    auto result = new_array<bool>(rows.lead);
    bool* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        const BatchOptions one = chunk_options(coherent);
        for_each_ray_chunk(rows, tnear.value_or(0.0f), tfar.value_or(kInfinity), threads, [&](const RayChunk& c) {
            uint8_t occluded[kBatchGrain];
            h.accel->occluded({c.rays.data, c.count}, {occluded, c.count}, one);
            if (!c.complete()) std::fill(out + c.begin, out + c.end, false);
            for (size_t k = 0; k < c.count; ++k) out[c.row(k)] = occluded[k] != 0;
        });
    }
    return result;
}

}  // namespace thicket::python

namespace thicket::python {

namespace {

/// Directions for the parity test of compute_occupancy: none along an axis or a diagonal, so that
/// rays from grid-aligned points do not run along the edges and faces of axis-aligned meshes.
constexpr Vec3 kParityDirections[] = {{0.5741f, 0.6327f, 0.5193f}, {-0.6811f, 0.2412f, 0.6913f},
                                      {0.3174f, -0.8479f, 0.4247f}, {-0.4431f, -0.5077f, -0.7389f},
                                      {0.7823f, -0.2291f, -0.5792f}};
constexpr int kMaxSamples = int(std::size(kParityDirections));

static_assert(sizeof(Vec3) == 3 * sizeof(float), "query points are read as Vec3 in place");

/// Query points as rows of 3 floats, every one finite: a NaN or infinite point has no closest
/// point and no inside, and the traversals assume finite origins, so it is refused up front.
Rows query_points(const py::handle& obj) {
    Rows rows = float32_rows(obj, "query_points", {3});
    const float* p = rows.data();
    for (size_t i = 0; i < 3 * rows.count; ++i)
        if (!std::isfinite(p[i]))
            throw py::value_error("query_points: point " + std::to_string(i / 3) + " (in row order) is not finite");
    return rows;
}

/// The structure that answers closest points: the user's own when it answers them natively
/// (brute, bvh, bvh8 over triangles), else a bvh8 over the same scene, built once on first use
/// (without the GIL; two threads racing both build, one result is kept).
const Accel& closest_accel(AccelHandle& h) {
    if (h.accel->has_closest_point()) return *h.accel;
    if (!h.closest_helper) {
        std::shared_ptr<const Accel> helper;
        {
            py::gil_scoped_release nogil;
            helper = build_accel("bvh8", *h.scene);
            if (!helper->has_closest_point()) helper->closest_point({0, 0, 0});  // throws the reason (shapes)
        }
        if (!h.closest_helper) h.closest_helper = std::move(helper);
    }
    return *h.closest_helper;
}

/// nsamples must be odd and at most kMaxSamples: a ValueError naming it otherwise.
void check_samples(int nsamples) {
    if (nsamples < 1 || nsamples > kMaxSamples || nsamples % 2 == 0)
        throw py::value_error("nsamples must be odd, between 1 and " + std::to_string(kMaxSamples) + ", got " +
                              std::to_string(nsamples));
}

/// Calls f(begin, end, closest) for the points in chunks of kBatchGrain on `threads` threads,
/// closest[k] being point begin + k's closest point; call without the GIL. As for rays, each
/// chunk's answers stay on the stack of the thread that writes them out.
template <class F>
void for_each_closest_chunk(const Accel& accel, const Rows& rows, unsigned threads, F&& f) {
    const auto* points = reinterpret_cast<const Vec3*>(rows.data());  // rows of 3 floats: Vec3's layout
    const BatchOptions one = chunk_options(false);
    parallel_for(rows.count, kBatchGrain, threads, [&](size_t begin, size_t end) {
        NearestPoint closest[kBatchGrain];
        accel.closest_points({points + begin, end - begin}, {closest, end - begin}, one);
        f(begin, end, static_cast<const NearestPoint*>(closest));
    });
}

/// inside[k] (1 or 0) of points [begin, end) by the parity of crossings along nsamples fixed
/// directions, the majority deciding; traced on the calling thread.
void inside_of(const Accel& accel, const Vec3* points, size_t begin, size_t end, int nsamples, uint8_t* inside) {
    const size_t n = end - begin;
    Ray rays[kBatchGrain];
    uint32_t counts[kBatchGrain];
    uint8_t votes[kBatchGrain] = {};
    const BatchOptions one = chunk_options(false);
    for (int s = 0; s < nsamples; ++s) {
        for (size_t k = 0; k < n; ++k) rays[k] = {points[begin + k], 0.0f, kParityDirections[s], kInfinity};
        accel.count_hits({rays, n}, {counts, n}, one);
        for (size_t k = 0; k < n; ++k) votes[k] += counts[k] & 1;
    }
    for (size_t k = 0; k < n; ++k) inside[k] = 2 * votes[k] > nsamples ? 1 : 0;
}

}  // namespace

py::array count_intersections(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    auto result = new_array<int32_t>(rows.lead);
    int32_t* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        const BatchOptions one = chunk_options(false);
        for_each_ray_chunk(rows, 0.0f, kInfinity, threads, [&](const RayChunk& c) {
            uint32_t counts[kBatchGrain];
            h.accel->count_hits({c.rays.data, c.count}, {counts, c.count}, one);
            if (!c.complete()) std::fill(out + c.begin, out + c.end, 0);
            for (size_t k = 0; k < c.count; ++k) out[c.row(k)] = int32_t(counts[k]);
        });
    }
    return result;
}

py::dict list_intersections(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    RayBatch batch;
    HitLists lists;
    {
        py::gil_scoped_release nogil;
        batch = make_rays(rows, 0.0f, kInfinity, threads);
        lists = h.accel->all_hits(batch.rays, batch_options(threads, false));
    }
    const size_t n = lists.hits.size();
    if (n > size_t(UINT32_MAX)) throw Error("list_intersections: more than 2^32 - 1 crossings; cast fewer rays at once");
    auto splits = new_array<uint32_t>({py::ssize_t(rows.count + 1)});
    auto ray_ids = new_array<uint32_t>({py::ssize_t(n)});
    auto t_hit = new_array<float>({py::ssize_t(n)});
    auto geometry_ids = new_array<uint32_t>({py::ssize_t(n)});
    auto primitive_ids = new_array<uint32_t>({py::ssize_t(n)});
    auto uvs = new_array<float>({py::ssize_t(n)}, {2});
    uint32_t* sp = splits.mutable_data();
    uint32_t* ids = ray_ids.mutable_data();
    float* t = t_hit.mutable_data();
    uint32_t* geom = geometry_ids.mutable_data();
    uint32_t* prim = primitive_ids.mutable_data();
    float* uv = uvs.mutable_data();
    {
        py::gil_scoped_release nogil;
        // Rows without a ray have no crossings: their split repeats the previous one.
        size_t k = 0;
        sp[0] = 0;
        for (size_t row = 0; row < rows.count; ++row) {
            const bool has_ray = k < batch.rays.size() && batch.row_of(k) == row;
            const size_t end = has_ray ? lists.splits[k + 1] : sp[row];
            for (size_t j = sp[row]; j < end; ++j) {
                const Hit& hit = lists.hits[j];
                ids[j] = uint32_t(row);
                t[j] = hit.t;
                geom[j] = kGeometryId;
                prim[j] = hit.prim;
                uv[2 * j] = hit.u;
                uv[2 * j + 1] = hit.v;
            }
            sp[row + 1] = uint32_t(end);
            k += has_ray;
        }
    }
    py::dict out;
    out["ray_splits"] = splits;
    out["ray_ids"] = ray_ids;
    out["t_hit"] = t_hit;
    out["geometry_ids"] = geometry_ids;
    out["primitive_ids"] = primitive_ids;
    out["primitive_uvs"] = uvs;
    return out;
}

py::dict compute_closest_points(AccelHandle& h, const py::handle& points_obj, unsigned threads) {
    const Rows rows = query_points(points_obj);
    const Accel& accel = closest_accel(h);
    auto points = new_array<float>(rows.lead, {3});
    auto geometry_ids = new_array<uint32_t>(rows.lead);
    auto primitive_ids = new_array<uint32_t>(rows.lead);
    auto uvs = new_array<float>(rows.lead, {2});
    auto normals = new_array<float>(rows.lead, {3});
    float* p = points.mutable_data();
    uint32_t* geom = geometry_ids.mutable_data();
    uint32_t* prim = primitive_ids.mutable_data();
    float* uv = uvs.mutable_data();
    float* nrm = normals.mutable_data();
    {
        py::gil_scoped_release nogil;
        for_each_closest_chunk(accel, rows, threads, [&](size_t begin, size_t end, const NearestPoint* closest) {
            for (size_t i = begin; i < end; ++i) {
                const NearestPoint& s = closest[i - begin];
                const bool found = s.found();
                p[3 * i] = s.point.x, p[3 * i + 1] = s.point.y, p[3 * i + 2] = s.point.z;
                geom[i] = found ? kGeometryId : kNoPrim;
                prim[i] = s.prim;
                uv[2 * i] = s.u, uv[2 * i + 1] = s.v;
                Vec3 n = found ? h.scene->geometric_normal(s.prim) : Vec3{0, 0, 0};
                if (dot(n, n) > 0) n = normalize(n);
                nrm[3 * i] = n.x, nrm[3 * i + 1] = n.y, nrm[3 * i + 2] = n.z;
            }
        });
    }
    py::dict out;
    out["points"] = points;
    out["geometry_ids"] = geometry_ids;
    out["primitive_ids"] = primitive_ids;
    out["primitive_uvs"] = uvs;
    out["primitive_normals"] = normals;
    return out;
}

py::array compute_distance(AccelHandle& h, const py::handle& points_obj, unsigned threads) {
    const Rows rows = query_points(points_obj);
    const Accel& accel = closest_accel(h);
    auto result = new_array<float>(rows.lead);
    float* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        for_each_closest_chunk(accel, rows, threads, [&](size_t begin, size_t end, const NearestPoint* closest) {
            for (size_t i = begin; i < end; ++i) out[i] = closest[i - begin].distance;
        });
    }
    return result;
}

py::array compute_occupancy(const AccelHandle& h, const py::handle& points_obj, unsigned threads, int nsamples) {
    const Rows rows = query_points(points_obj);
    check_samples(nsamples);
    auto result = new_array<float>(rows.lead);
    float* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        const auto* points = reinterpret_cast<const Vec3*>(rows.data());
        parallel_for(rows.count, kBatchGrain, threads, [&](size_t begin, size_t end) {
            uint8_t inside[kBatchGrain];
            inside_of(*h.accel, points, begin, end, nsamples, inside);
            for (size_t i = begin; i < end; ++i) out[i] = inside[i - begin] ? 1.0f : 0.0f;
        });
    }
    return result;
}

py::array compute_signed_distance(AccelHandle& h, const py::handle& points_obj, unsigned threads, int nsamples) {
    const Rows rows = query_points(points_obj);
    check_samples(nsamples);
    const Accel& accel = closest_accel(h);
    auto result = new_array<float>(rows.lead);
    float* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        const auto* points = reinterpret_cast<const Vec3*>(rows.data());
        for_each_closest_chunk(accel, rows, threads, [&](size_t begin, size_t end, const NearestPoint* closest) {
            uint8_t inside[kBatchGrain];
            inside_of(*h.accel, points, begin, end, nsamples, inside);
            for (size_t i = begin; i < end; ++i)
                out[i] = inside[i - begin] ? -closest[i - begin].distance : closest[i - begin].distance;
        });
    }
    return result;
}

double batch_seconds(AccelHandle& h, const py::handle& rows_obj, const std::string& query, unsigned threads) {
    BatchOptions options;
    options.threads = threads;
    if (query == "closest_point") {
        const Rows rows = query_points(rows_obj);
        const Accel& accel = closest_accel(h);
        py::gil_scoped_release nogil;
        const auto* p = reinterpret_cast<const Vec3*>(rows.data());
        const std::vector<Vec3> points(p, p + rows.count);
        std::vector<NearestPoint> out(rows.count);
        const auto start = std::chrono::steady_clock::now();
        accel.closest_points(points, out, options);
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (query != "closest" && query != "any" && query != "count")
        throw py::value_error("query must be closest, any, count or closest_point, got " + query);
    const Rows rows = float32_rows(rows_obj, "rays", {6, 8});
    py::gil_scoped_release nogil;
    const RayBatch batch = make_rays(rows, 0.0f, kInfinity, threads);
    std::vector<Hit> hits(query == "closest" ? batch.rays.size() : 0);
    std::vector<uint8_t> occluded(query == "any" ? batch.rays.size() : 0);
    std::vector<uint32_t> counts(query == "count" ? batch.rays.size() : 0);
    const auto start = std::chrono::steady_clock::now();
    if (query == "closest")
        h.accel->intersect(batch.rays, hits, options);
    else if (query == "any")
        h.accel->occluded(batch.rays, occluded, options);
    else
        h.accel->count_hits(batch.rays, counts, options);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace thicket::python
