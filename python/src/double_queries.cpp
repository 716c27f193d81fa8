#include "double_queries.h"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "thicket/query/double_rays.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket::python {

namespace {

/// A float64 array's rows and their rays (query/double_rays.h: a row without a meaning is
/// answered as a miss, as float rows are).
struct DoubleRays {
    RowsD rows;
    RayBatchD batch;
};

/// `obj`'s rows (..., 6) or (..., 8) as double rays for `query`, rows of 6 taking [tnear, tfar];
/// `answer_bytes` per row is what the query's answers will take, checked with the rays'.
DoubleRays double_rays(const AccelHandle& h, const py::handle& obj, const char* query, size_t answer_bytes,
                       unsigned threads, std::optional<float> tnear = {}, std::optional<float> tfar = {}) {
    if (!h.accel->double_precision())
        throw py::value_error(
            float64_rays_refusal("rays", "'" + h.accel->spec() + "'", "convert the rays with .astype(numpy.float32)"));
    DoubleRays out{typed_rows<double>(obj, "rays", {6, 8}, ""), {}};
    const RowsD& rows = out.rows;
    check_interval_arguments(rows, tnear, tfar);
    check_answer_memory(rows, sizeof(RayD) + 1 + answer_bytes, query);
    RayRowsD in{rows.data(), rows.count, rows.width};
    if (tnear) in.tmin = double(*tnear);
    if (tfar) in.tmax = double(*tfar);
    out.batch = make_rays(in, threads);
    return out;
}

}  // namespace

bool is_float64_array(const py::handle& obj) {
    return py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).dtype().is(py::dtype::of<double>());
}

py::dict cast_rays_double(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    // The hits, then t, two ids, uv and normal.
    const DoubleRays in = double_rays(h, rays_obj, "cast_rays", sizeof(HitD) + 8 + 4 + 4 + 16 + 12, threads);
    CastArrays<double> a(in.rows.lead);
    double* t = a.t_hit.mutable_data();
    uint32_t* geom = a.geometry_ids.mutable_data();
    uint32_t* prim = a.primitive_ids.mutable_data();
    double* uv = a.uvs.mutable_data();
    float* nrm = a.normals.mutable_data();
    {
        py::gil_scoped_release nogil;
        std::vector<HitD> hits(in.batch.size());
        closest_hits(*h.accel, in.batch, hits, on_threads(threads));
        parallel_for(hits.size(), kBatchGrain, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                const HitD& hit = hits[i];
                const bool found = hit.found();
                const RayD& r = in.batch.rays[i];
                const Vec3 n = found ? h.scene->normal(Ray{r.org.to_float(), 0.0f, r.dir.to_float(), kInfinity},
                                                       to_hit(hit))
                                     : Vec3{0, 0, 0};
                t[i] = found ? hit.t : std::numeric_limits<double>::infinity();
                geom[i] = h.scene->geometry_of(hit.prim);
                prim[i] = hit.prim;
                uv[2 * i] = found ? hit.u : 0.0;
                uv[2 * i + 1] = found ? hit.v : 0.0;
                nrm[3 * i] = n.x;
                nrm[3 * i + 1] = n.y;
                nrm[3 * i + 2] = n.z;
            }
        });
    }
    return a.answer();
}

py::array test_occlusions_double(const AccelHandle& h, const py::handle& rays_obj, std::optional<float> tnear,
                                 std::optional<float> tfar, unsigned threads) {
    const DoubleRays in = double_rays(h, rays_obj, "test_occlusions", 2 * sizeof(bool), threads, tnear, tfar);
    auto result = new_array<bool>(in.rows.lead);
    {
        py::gil_scoped_release nogil;
        std::vector<uint8_t> occluded(in.batch.size());
        occlusions(*h.accel, in.batch, occluded, on_threads(threads));
        std::copy(occluded.begin(), occluded.end(), result.mutable_data());
    }
    return result;
}

py::array count_intersections_double(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const DoubleRays in =
        double_rays(h, rays_obj, "count_intersections", sizeof(int32_t) + sizeof(uint32_t), threads);
    std::vector<uint32_t> counts(in.batch.size());
    {
        py::gil_scoped_release nogil;
        crossing_counts(*h.accel, in.batch, counts, on_threads(threads));
    }
    auto result = new_array<int32_t>(in.rows.lead);
    std::copy(counts.begin(), counts.end(), result.mutable_data());
    return result;
}

py::dict list_intersections_double(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const DoubleRays in =
        double_rays(h, rays_obj, "list_intersections", sizeof(uint32_t) + sizeof(size_t), threads);
    const size_t rays = in.batch.size();
    std::vector<uint32_t> counts(rays);
    {
        py::gil_scoped_release nogil;
        crossing_counts(*h.accel, in.batch, counts, on_threads(threads));
    }
    uint64_t n = 0;
    for (const uint32_t c : counts) n += c;
    if (n > uint64_t(UINT32_MAX)) throw Error("list_intersections: more than 2^32 - 1 crossings; cast fewer rays at once");
    // Each crossing as HitD (32 bytes) while listed, then ray id, t, two ids and uv (36).
    check_allocation(bytes_of(n, sizeof(HitD) + 36),
                     "list_intersections: the " + std::to_string(n) + " crossings of " + std::to_string(rays) + " rays");
    HitListsD lists;
    {
        py::gil_scoped_release nogil;
        lists = crossing_lists(*h.accel, in.batch, counts, on_threads(threads));
    }
    return intersection_lists_answer<double>(*h.scene, lists, rays);
}

}  // namespace thicket::python
