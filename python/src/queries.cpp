#include "queries.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <vector>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket::python {

namespace {

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
    auto normals = std::make_shared<std::vector<Vec3>>(h.scene->mesh.triangle_count());
    {
        py::gil_scoped_release nogil;
        parallel_for(normals->size(), 4096, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) (*normals)[i] = h.scene->normal(Ray{}, Hit{0.0f, 0.0f, 0.0f, uint32_t(i)});
        });
    }
    if (!h.triangle_normals) h.triangle_normals = std::move(normals);
    return h.triangle_normals;
}

}  // namespace

py::dict cast_rays(AccelHandle& h, const py::handle& rays_obj, unsigned threads, bool coherent) {
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    const std::shared_ptr<const std::vector<Vec3>> normal_table = triangle_normals(h, threads);
    const Vec3* table = normal_table ? normal_table->data() : nullptr;
    // numpy allocates without touching: the worker threads that write a chunk's answers take its
    // pages' first-touch faults, in parallel and next to the tracing.
    auto t_hit = new_array<float>(rows.lead);
    auto geometry_ids = new_array<uint32_t>(rows.lead);
    auto primitive_ids = new_array<uint32_t>(rows.lead);
    auto uvs = new_array<float>(rows.lead, {2});
    auto normals = new_array<float>(rows.lead, {3});
    // Raw pointers taken with the GIL held; the arrays stay alive in this frame.
    float* t = t_hit.mutable_data();
    uint32_t* geom = geometry_ids.mutable_data();
    uint32_t* prim = primitive_ids.mutable_data();
    float* uv = uvs.mutable_data();
    float* nrm = normals.mutable_data();
    {
        py::gil_scoped_release nogil;
        const BatchOptions one = chunk_options(coherent);
        for_each_ray_chunk(rows, 0.0f, kInfinity, threads, [&](const RayChunk& c) {
            Hit hits[kBatchGrain];
            h.accel->intersect({c.rays, c.count}, {hits, c.count}, one);
            if (!c.complete())  // rows without a ray are misses
                for (size_t row = c.begin; row < c.end; ++row) {
                    t[row] = kInfinity;
                    geom[row] = prim[row] = kNoPrim;
                    uv[2 * row] = uv[2 * row + 1] = 0.0f;
                    nrm[3 * row] = nrm[3 * row + 1] = nrm[3 * row + 2] = 0.0f;
                }
            for (size_t k = 0; k < c.count; ++k) {
                const size_t row = c.row(k);
                const Hit& hit = hits[k];
                const bool found = hit.found();
                // A miss is +inf, not the ray's tmax (Open3D's and `thicket trace`'s convention).
                t[row] = found ? hit.t : kInfinity;
                geom[row] = found ? 0u : kNoPrim;
                prim[row] = found ? hit.prim : kNoPrim;
                uv[2 * row] = found ? hit.u : 0.0f;
                uv[2 * row + 1] = found ? hit.v : 0.0f;
                const Vec3 n = !found ? Vec3{0, 0, 0} : table ? table[hit.prim] : h.scene->normal(c.rays[k], hit);
                nrm[3 * row] = n.x, nrm[3 * row + 1] = n.y, nrm[3 * row + 2] = n.z;
            }
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
            h.accel->occluded({c.rays, c.count}, {occluded, c.count}, one);
            if (!c.complete()) std::fill(out + c.begin, out + c.end, false);
            for (size_t k = 0; k < c.count; ++k) out[c.row(k)] = occluded[k] != 0;
        });
    }
    return result;
}

}  // namespace thicket::python

namespace thicket::python {

namespace {

constexpr uint32_t kGeometryId = 0;  // one geometry per structure (Open3D numbers its meshes)

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
            h.accel->count_hits({c.rays, c.count}, {counts, c.count}, one);
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
