#include "double_queries.h"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "thicket/util/parallel.h"

namespace thicket::python {

namespace {

/// The rays of a float64 array as RayD, with whether each means anything (make_ray_double: a
/// ray that does not is answered as a miss, as float rows are).
struct DoubleRays {
    std::vector<py::ssize_t> lead;
    std::vector<RayD> rays;
    std::vector<uint8_t> valid;
};

DoubleRays double_rays(const AccelHandle& h, const py::handle& obj, double tnear, double tfar) {
    if (!h.accel->double_precision())
        throw py::value_error("rays: float64 rays are traced by structures built with precision=double (e.g. "
                              "'bvh:precision=double'), and this one is '" +
                              h.accel->spec() + "': build one with precision=double, or convert the rays with "
                                                ".astype(numpy.float32)");
    const py::array a = py::reinterpret_borrow<py::array>(obj);
    const size_t width = a.ndim() >= 1 ? size_t(a.shape(a.ndim() - 1)) : 0;
    if (width != 6 && width != 8)
        throw py::value_error("rays: expected shape (..., 6) or (..., 8), got shape " + shape_text(a) + " float64");
    DoubleRays out;
    size_t count = 1;
    for (py::ssize_t i = 0; i + 1 < a.ndim(); ++i) {
        out.lead.push_back(a.shape(i));
        count *= size_t(a.shape(i));
    }
    check_allocation(bytes_of(count, sizeof(RayD) + 1 + 40), "float64 rays of shape " + shape_text(a));
    const py::array rows = contiguous(a, py::dtype::of<double>(), "rays");
    const double* data = static_cast<const double*>(rows.data());
    out.rays.resize(count);
    out.valid.resize(count);
    for (size_t i = 0; i < count; ++i) {
        double r[8];
        std::copy(data + i * width, data + i * width + 6, r);
        r[6] = width == 8 ? data[i * width + 6] : tnear;
        r[7] = width == 8 ? data[i * width + 7] : tfar;
        out.valid[i] = make_ray_double(r, out.rays[i]) ? 1 : 0;
    }
    return out;
}

}  // namespace

bool is_float64_array(const py::handle& obj) {
    return py::isinstance<py::array>(obj) && py::reinterpret_borrow<py::array>(obj).dtype().is(py::dtype::of<double>());
}

py::dict cast_rays_double(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const DoubleRays in = double_rays(h, rays_obj, 0.0, std::numeric_limits<double>::infinity());
    auto t_hit = new_array<double>(in.lead);
    auto geometry_ids = new_array<uint32_t>(in.lead);
    auto primitive_ids = new_array<uint32_t>(in.lead);
    auto uvs = new_array<double>(in.lead, {2});
    auto normals = new_array<float>(in.lead, {3});
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

py::array test_occlusions_double(const AccelHandle& h, const py::handle& rays_obj, std::optional<double> tnear,
                                 std::optional<double> tfar, unsigned threads) {
    const DoubleRays in = double_rays(h, rays_obj, tnear.value_or(0.0),
                                      tfar.value_or(std::numeric_limits<double>::infinity()));
    auto result = new_array<bool>(in.lead);
    bool* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        parallel_for(in.rays.size(), kBatchGrain, threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) out[i] = in.valid[i] && h.accel->occluded_double(in.rays[i]);
        });
    }
    return result;
}

}  // namespace thicket::python
