#include "queries.h"

#include "double_queries.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <span>
#include <vector>

#include "thicket/query/hit_columns.h"
#include "thicket/query/point_queries.h"
#include "thicket/query/ray_rows.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket::python {

namespace {

/// h.triangle_normals, made on first use for a triangle scene (null for a scene with shapes or instances,
/// whose normals depend on the hit point). Call with the GIL held; it is released while the
/// normals are computed, in parallel, with Scene::normal itself, so that they are its bits.
std::shared_ptr<const std::vector<Vec3>> triangle_normals(AccelHandle& h, unsigned threads) {
    // With instances hit.prim is a flattened id, which no per-triangle table covers.
    if (h.triangle_normals || h.scene->has_shapes() || !h.scene->instances.empty()) return h.triangle_normals;
    const size_t count = h.scene->mesh.triangle_count();
    // Two zero entries past the last: a miss's normal (HitColumns::put_chunk), and room for reading
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

}  // namespace

py::dict cast_rays(AccelHandle& h, const py::handle& rays_obj, unsigned threads, bool coherent) {
    if (is_float64_array(rays_obj)) {
        BatchOptions options;
        options.coherent = coherent;
        refuse_coherent("float64 cast_rays", options);
        return cast_rays_double(h, rays_obj, threads);
    }
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    check_answer_memory(rows, 4 + 4 + 4 + 8 + 12, "cast_rays");  // t, two ids, uv, normal
    const std::shared_ptr<const std::vector<Vec3>> normal_table = triangle_normals(h, threads);
    const Vec3* table = normal_table && normal_table->size() > 2 ? normal_table->data() : nullptr;
    const uint32_t miss_entry = normal_table ? uint32_t(normal_table->size() - 2) : 0;
    CastArrays<float> a(rows.lead);
    // Taken with the GIL held; the arrays stay alive in this frame.
    HitColumns o{a.t_hit.mutable_data(), a.geometry_ids.mutable_data(), a.primitive_ids.mutable_data(),
                 a.uvs.mutable_data(), a.normals.mutable_data(), h.scene.get()};
    o.stream_when_large(rows.count);
    {
        py::gil_scoped_release nogil;
        for_each_ray_chunk(ray_rows(rows), threads, reorder_from(BatchOptions{}), [&](const RayChunk& c) {
            Uninitialized<Hit> hits;
            h.accel->intersect_chunk(c.span(), {hits.data, c.count}, coherent);
            o.put_chunk(c, hits.data, table, miss_entry);
        });
    }
    return a.answer();
}

py::array test_occlusions(const AccelHandle& h, const py::handle& rays_obj, std::optional<float> tnear,
                          std::optional<float> tfar, unsigned threads, bool coherent) {
    BatchOptions options;
    options.coherent = coherent;
    refuse_coherent("test_occlusions", options);  // no any-hit packet path
    if (is_float64_array(rays_obj)) return test_occlusions_double(h, rays_obj, tnear, tfar, threads);
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    check_interval_arguments(rows, tnear, tfar);
    check_answer_memory(rows, sizeof(bool), "test_occlusions");
    auto result = new_array<bool>(rows.lead);
    bool* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        for_each_ray_chunk(ray_rows(rows, tnear.value_or(0.0f), tfar.value_or(kInfinity)), threads, reorder_from(options),
                           [&](const RayChunk& c) {
            uint8_t occluded[kBatchGrain];
            h.accel->occluded_chunk(c.span(), {occluded, c.count});
            c.for_each_row_without_ray([&](size_t row) { out[row] = false; });
            for (size_t k = 0; k < c.count; ++k) out[c.row(k)] = occluded[k] != 0;
        });
    }
    return result;
}

}  // namespace thicket::python

namespace thicket::python {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(float), "query points are read as Vec3 in place");

/// Rows of 3 floats as points, in place.
std::span<const Vec3> points_of(const Rows& rows) {
    return {reinterpret_cast<const Vec3*>(rows.data()), rows.count};
}

/// Query points as rows of 3 floats, every one finite: a NaN or infinite point has no closest
/// point and no inside, and the traversals assume finite origins, so it is refused up front.
/// float64 points are refused naming the precision `query` needs: closest points and occupancy
/// are computed in float32 by every structure (precision=double has no point queries), and
/// rounding the points here would hide that.
Rows query_points(const py::handle& obj, const char* query) {
    if (is_float64_array(obj))
        throw py::value_error("query_points: expected dtype float32, got shape " +
                              shape_text(py::reinterpret_borrow<py::array>(obj)) + " float64: " + std::string(query) +
                              " takes float32 points only (closest points, distances and occupancy are computed in "
                              "float32 by every structure, precision=double ones included); convert with "
                              ".astype(numpy.float32)");
    Rows rows = float32_rows(obj, "query_points", {3});
    const size_t bad = first_non_finite(points_of(rows));
    if (bad < rows.count)
        throw py::value_error("query_points: point " + std::to_string(bad) + " (in row order) is not finite");
    return rows;
}

/// nsamples must be odd and at most kMaxParitySamples: a ValueError naming it otherwise.
void check_samples(int nsamples) {
    try {
        check_parity_samples(nsamples);
    } catch (const Error& e) {
        throw py::value_error(e.what());
    }
}

/// The structure that answers closest points, built (once, without the GIL) on first use.
const Accel& closest_accel(const AccelHandle& h) {
    py::gil_scoped_release nogil;
    return h.points->closest_accel();
}

}  // namespace

py::array count_intersections(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    if (is_float64_array(rays_obj)) return count_intersections_double(h, rays_obj, threads);
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    check_answer_memory(rows, sizeof(int32_t), "count_intersections");
    auto result = new_array<int32_t>(rows.lead);
    int32_t* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        for_each_ray_chunk(ray_rows(rows), threads, reorder_from(BatchOptions{}), [&](const RayChunk& c) {
            c.for_each_row_without_ray([&](size_t row) { out[row] = 0; });
            for (size_t k = 0; k < c.count; ++k) out[c.row(k)] = int32_t(h.accel->count_hits(c.rays.data[k]));
        });
    }
    return result;
}

py::dict list_intersections(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    if (is_float64_array(rays_obj)) return list_intersections_double(h, rays_obj, threads);
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    HitLists lists;
    {
        py::gil_scoped_release nogil;
        lists = crossing_lists(*h.accel, ray_rows(rows), on_threads(threads));
    }
    const size_t n = lists.hits.size();
    if (n > size_t(UINT32_MAX)) throw Error("list_intersections: more than 2^32 - 1 crossings; cast fewer rays at once");
    // The ray ids, t, geometry and primitive ids and uvs of every crossing, and the splits.
    check_allocation(bytes_of(n, 24) + bytes_of(rows.count + 1, 4),
                     "list_intersections: the " + std::to_string(n) + " crossings of " + std::to_string(rows.count) + " rays");
    return intersection_lists_answer<float>(*h.scene, lists, rows.count);
}

py::dict compute_closest_points(AccelHandle& h, const py::handle& points_obj, unsigned threads) {
    const Rows rows = query_points(points_obj, "compute_closest_points");
    check_answer_memory(rows, 12 + 4 + 4 + 8 + 12, "compute_closest_points");  // point, two ids, uv, normal
    closest_accel(h);
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
        h.points->for_each_closest_chunk(points_of(rows), threads, [&](size_t begin, size_t end, const NearestPoint* closest) {
            for (size_t i = begin; i < end; ++i) {
                const NearestPoint& s = closest[i - begin];
                const bool found = s.found();
                p[3 * i] = s.point.x, p[3 * i + 1] = s.point.y, p[3 * i + 2] = s.point.z;
                geom[i] = found ? h.scene->geometry_of(s.prim) : kNoPrim;
                prim[i] = s.prim;
                uv[2 * i] = s.u, uv[2 * i + 1] = s.v;
                Vec3 n = found ? h.scene->geometric_normal(s.prim) : Vec3{0, 0, 0};
                if (dot(n, n) > 0) n = normalize(n);
                nrm[3 * i] = n.x, nrm[3 * i + 1] = n.y, nrm[3 * i + 2] = n.z;
            }
        });
    }
    return named_answers({{"points", points}, {"geometry_ids", geometry_ids}, {"primitive_ids", primitive_ids},
                          {"primitive_uvs", uvs}, {"primitive_normals", normals}});
}

py::array compute_distance(AccelHandle& h, const py::handle& points_obj, unsigned threads) {
    const Rows rows = query_points(points_obj, "compute_distance");
    check_answer_memory(rows, sizeof(float), "compute_distance");
    closest_accel(h);
    auto result = new_array<float>(rows.lead);
    {
        py::gil_scoped_release nogil;
        h.points->distances(points_of(rows), {result.mutable_data(), rows.count}, on_threads(threads));
    }
    return result;
}

py::array compute_occupancy(const AccelHandle& h, const py::handle& points_obj, unsigned threads, int nsamples) {
    const Rows rows = query_points(points_obj, "compute_occupancy");
    check_samples(nsamples);
    check_answer_memory(rows, sizeof(float), "compute_occupancy");
    auto result = new_array<float>(rows.lead);
    float* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        const std::span<const Vec3> points = points_of(rows);
        parallel_for(rows.count, kBatchGrain, threads, [&](size_t begin, size_t end) {
            uint8_t inside[kBatchGrain];
            inside_by_parity(*h.accel, points.subspan(begin, end - begin), nsamples, {inside, end - begin});
            for (size_t i = begin; i < end; ++i) out[i] = inside[i - begin] ? 1.0f : 0.0f;
        });
    }
    return result;
}

py::array compute_signed_distance(AccelHandle& h, const py::handle& points_obj, unsigned threads, int nsamples) {
    const Rows rows = query_points(points_obj, "compute_signed_distance");
    check_samples(nsamples);
    check_answer_memory(rows, sizeof(float), "compute_signed_distance");
    closest_accel(h);
    auto result = new_array<float>(rows.lead);
    {
        py::gil_scoped_release nogil;
        h.points->signed_distances(points_of(rows), {result.mutable_data(), rows.count}, nsamples, on_threads(threads));
    }
    return result;
}

double batch_seconds(AccelHandle& h, const py::handle& rows_obj, const std::string& query, unsigned threads) {
    const BatchOptions options = on_threads(threads);
    if (query == "closest_point") {
        const Rows rows = query_points(rows_obj, "_batch_seconds");
        check_answer_memory(rows, sizeof(Vec3) + sizeof(NearestPoint), "_batch_seconds");
        const Accel& accel = closest_accel(h);
        py::gil_scoped_release nogil;
        const std::span<const Vec3> rows_points = points_of(rows);
        const std::vector<Vec3> points(rows_points.begin(), rows_points.end());
        std::vector<NearestPoint> out(rows.count);
        const auto start = std::chrono::steady_clock::now();
        accel.closest_points(points, out, options);
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (query != "closest" && query != "any" && query != "count")
        throw py::value_error("query must be closest, any, count or closest_point, got " + query);
    const Rows rows = float32_rows(rows_obj, "rays", {6, 8});
    check_answer_memory(rows, sizeof(Ray) + sizeof(Hit), "_batch_seconds");
    py::gil_scoped_release nogil;
    const RayBatch batch = make_rays(ray_rows(rows), threads);
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
