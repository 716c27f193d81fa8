#include "double_queries.h"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "thicket/accel/crossings_double.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket::python {

namespace {

/// The rays of a float64 array as RayD, with whether each means anything (make_ray_double: a
/// ray that does not is answered as a miss, as float rows are).
struct DoubleRays {
    RowsD rows;
    std::vector<RayD> rays;
    std::vector<uint8_t> valid;
};

/// `obj`'s rows (..., 6) or (..., 8) as double rays for `query`, rows of 6 taking [tnear, tfar];
/// `answer_bytes` per row is what the query's answers will take, checked with the rays'.
DoubleRays double_rays(const AccelHandle& h, const py::handle& obj, const char* query, size_t answer_bytes,
                       std::optional<float> tnear = {}, std::optional<float> tfar = {}) {
    if (!h.accel->double_precision())
        throw py::value_error("rays: float64 rays are traced by structures built with precision=double (e.g. "
                              "'bvh:precision=double'), and this one is '" +
                              h.accel->spec() + "': build one with precision=double, or convert the rays with "
                                                ".astype(numpy.float32)");
    DoubleRays out{typed_rows<double>(obj, "rays", {6, 8}, ""), {}, {}};
    const RowsD& rows = out.rows;
    check_interval_arguments(rows, tnear, tfar);
    check_answer_memory(rows, sizeof(RayD) + 1 + answer_bytes, query);
    const double lo = tnear ? double(*tnear) : 0.0;
    const double hi = tfar ? double(*tfar) : std::numeric_limits<double>::infinity();
    const double* data = rows.data();
    const size_t width = rows.width;
    out.rays.resize(rows.count);
    out.valid.resize(rows.count);
    for (size_t i = 0; i < rows.count; ++i) {
        double r[8];
        std::copy(data + i * width, data + i * width + 6, r);
        r[6] = width == 8 ? data[i * width + 6] : lo;
        r[7] = width == 8 ? data[i * width + 7] : hi;
        out.valid[i] = make_ray_double(r, out.rays[i]) ? 1 : 0;
    }
    return out;
}

}  // namespace

bool is_float64_array(const py::handle& obj) {
    return py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).dtype().is(py::dtype::of<double>());
}

py::dict cast_rays_double(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const DoubleRays in = double_rays(h, rays_obj, "cast_rays", 8 + 4 + 4 + 16 + 12);  // t, two ids, uv, normal
    const std::vector<py::ssize_t>& lead = in.rows.lead;
    auto t_hit = new_array<double>(lead);
    auto geometry_ids = new_array<uint32_t>(lead);
    auto primitive_ids = new_array<uint32_t>(lead);
    auto uvs = new_array<double>(lead, {2});
    auto normals = new_array<float>(lead, {3});
    double* t = t_hit.mutable_data();
    uint32_t* geom = geometry_ids.mutable_data();
    uint32_t* prim = primitive_ids.mutable_data();
    double* uv = uvs.mutable_data();
    float* nrm = normals.mutable_data();
    {
        py::gil_scoped_release nogil;
        parallel_for(in.rays.size(), kBatchGrain, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                const HitD hit = in.valid[i] ? h.accel->intersect_double(in.rays[i]) : HitD{};
                const bool found = hit.found();
                const RayD& r = in.rays[i];
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
    py::dict out;
    out["t_hit"] = t_hit;
    out["geometry_ids"] = geometry_ids;
    out["primitive_ids"] = primitive_ids;
    out["primitive_uvs"] = uvs;
    out["primitive_normals"] = normals;
    return out;
}

py::array test_occlusions_double(const AccelHandle& h, const py::handle& rays_obj, std::optional<float> tnear,
                                 std::optional<float> tfar, unsigned threads) {
    const DoubleRays in = double_rays(h, rays_obj, "test_occlusions", sizeof(bool), tnear, tfar);
    auto result = new_array<bool>(in.rows.lead);
    bool* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        parallel_for(in.rays.size(), kBatchGrain, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) out[i] = in.valid[i] && h.accel->occluded_double(in.rays[i]);
        });
    }
    return result;
}

py::array count_intersections_double(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const DoubleRays in = double_rays(h, rays_obj, "count_intersections", sizeof(int32_t) + sizeof(uint32_t));
    std::vector<uint32_t> counts(in.rays.size());
    {
        py::gil_scoped_release nogil;
        count_hits_double(*h.accel, in.rays, in.valid, counts, threads);
    }
    auto result = new_array<int32_t>(in.rows.lead);
    std::copy(counts.begin(), counts.end(), result.mutable_data());
    return result;
}

py::dict list_intersections_double(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const DoubleRays in = double_rays(h, rays_obj, "list_intersections", sizeof(uint32_t) + sizeof(size_t));
    const size_t rays = in.rays.size();
    std::vector<uint32_t> counts(rays);
    {
        py::gil_scoped_release nogil;
        count_hits_double(*h.accel, in.rays, in.valid, counts, threads);
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
        lists = list_hits_double(*h.accel, in.rays, in.valid, counts, threads);
    }
    return intersection_lists_answer<double>(*h.scene, lists, rays);
}

}  // namespace thicket::python
