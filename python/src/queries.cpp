#include "queries.h"

#include <algorithm>
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

}  // namespace

py::dict cast_rays(const AccelHandle& h, const py::handle& rays_obj, unsigned threads, bool coherent) {
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
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
        const RayBatch batch = make_rays(rows, 0.0f, kInfinity, threads);
        std::vector<Hit> hits(batch.rays.size());
        h.accel->intersect(batch.rays, hits, batch_options(threads, coherent));
        auto write = [&](size_t row, const Ray* ray, const Hit& hit) {
            const bool found = ray && hit.found();
            // A miss is +inf, not the ray's tmax (Open3D's and `thicket trace`'s convention).
            t[row] = found ? hit.t : kInfinity;
            geom[row] = found ? 0u : kNoPrim;
            prim[row] = found ? hit.prim : kNoPrim;
            uv[2 * row] = found ? hit.u : 0.0f;
            uv[2 * row + 1] = found ? hit.v : 0.0f;
            const Vec3 n = found ? h.scene->normal(*ray, hit) : Vec3{0, 0, 0};
            nrm[3 * row] = n.x, nrm[3 * row + 1] = n.y, nrm[3 * row + 2] = n.z;
        };
        if (batch.compacted)  // rows without a ray are misses
            parallel_for(rows.count, 4 * kBatchGrain, threads, [&](size_t b, size_t e) {
                for (size_t i = b; i < e; ++i) write(i, nullptr, Hit{});
            });
        parallel_for(hits.size(), 4 * kBatchGrain, threads, [&](size_t b, size_t e) {
            for (size_t k = b; k < e; ++k) write(batch.row_of(k), &batch.rays[k], hits[k]);
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
        const RayBatch batch = make_rays(rows, tnear.value_or(0.0f), tfar.value_or(kInfinity), threads);
        std::vector<uint8_t> occluded(batch.rays.size());
        h.accel->occluded(batch.rays, occluded, batch_options(threads, coherent));
        if (batch.compacted) std::fill(out, out + rows.count, false);
        for (size_t k = 0; k < occluded.size(); ++k) out[batch.row_of(k)] = occluded[k] != 0;
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

const Accel& closest_accel(AccelHandle& h) {
    if (h.accel->has_closest_point()) return *h.accel;
    if (!h.closest_helper) {
        std::shared_ptr<const Accel> bvh = build_accel("bvh", *h.scene);
        if (!bvh->has_closest_point()) bvh->closest_point({0, 0, 0});  // throws the reason (shapes)
        h.closest_helper = std::move(bvh);
    }
    return *h.closest_helper;
}

std::vector<NearestPoint> closest_of(AccelHandle& h, const Rows& rows, unsigned threads) {
    const Accel& accel = closest_accel(h);
    py::gil_scoped_release nogil;
    std::vector<NearestPoint> out(rows.count);
    const auto* points = reinterpret_cast<const Vec3*>(rows.data());  // rows of 3 floats: Vec3's layout
    accel.closest_points({points, rows.count}, out, batch_options(threads, false));
    return out;
}

std::vector<uint8_t> inside_of(const AccelHandle& h, const Rows& rows, unsigned threads, int nsamples) {
    if (nsamples < 1 || nsamples > kMaxSamples || nsamples % 2 == 0)
        throw py::value_error("nsamples must be odd, between 1 and " + std::to_string(kMaxSamples) + ", got " +
                              std::to_string(nsamples));
    py::gil_scoped_release nogil;
    std::vector<uint8_t> votes(rows.count, 0);
    std::vector<Ray> rays(rows.count);
    std::vector<uint32_t> counts(rows.count);
    const auto* points = reinterpret_cast<const Vec3*>(rows.data());
    for (int s = 0; s < nsamples; ++s) {
        for (size_t i = 0; i < rows.count; ++i) rays[i] = {points[i], 0.0f, kParityDirections[s], kInfinity};
        h.accel->count_hits(rays, counts, batch_options(threads, false));
        for (size_t i = 0; i < rows.count; ++i) votes[i] += counts[i] & 1;
    }
    for (uint8_t& v : votes) v = 2 * v > nsamples ? 1 : 0;
    return votes;
}

}  // namespace

py::array count_intersections(const AccelHandle& h, const py::handle& rays_obj, unsigned threads) {
    const Rows rows = float32_rows(rays_obj, "rays", {6, 8});
    auto result = new_array<int32_t>(rows.lead);
    int32_t* out = result.mutable_data();
    {
        py::gil_scoped_release nogil;
        const RayBatch batch = make_rays(rows, 0.0f, kInfinity, threads);
        std::vector<uint32_t> counts(batch.rays.size());
        h.accel->count_hits(batch.rays, counts, batch_options(threads, false));
        if (batch.compacted) std::fill(out, out + rows.count, 0);
        for (size_t k = 0; k < counts.size(); ++k) out[batch.row_of(k)] = int32_t(counts[k]);
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
    const std::vector<NearestPoint> closest = closest_of(h, rows, threads);
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
    for (size_t i = 0; i < rows.count; ++i) {
        const NearestPoint& s = closest[i];
        const bool found = s.found();
        p[3 * i] = s.point.x, p[3 * i + 1] = s.point.y, p[3 * i + 2] = s.point.z;
        geom[i] = found ? kGeometryId : kNoPrim;
        prim[i] = s.prim;
        uv[2 * i] = s.u, uv[2 * i + 1] = s.v;
        Vec3 n = found ? h.scene->geometric_normal(s.prim) : Vec3{0, 0, 0};
        if (dot(n, n) > 0) n = normalize(n);
        nrm[3 * i] = n.x, nrm[3 * i + 1] = n.y, nrm[3 * i + 2] = n.z;
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
    const std::vector<NearestPoint> closest = closest_of(h, rows, threads);
    auto result = new_array<float>(rows.lead);
    float* out = result.mutable_data();
    for (size_t i = 0; i < rows.count; ++i) out[i] = closest[i].distance;
    return result;
}

py::array compute_occupancy(const AccelHandle& h, const py::handle& points_obj, unsigned threads, int nsamples) {
    const Rows rows = query_points(points_obj);
    const std::vector<uint8_t> inside = inside_of(h, rows, threads, nsamples);
    auto result = new_array<float>(rows.lead);
    float* out = result.mutable_data();
    for (size_t i = 0; i < rows.count; ++i) out[i] = inside[i] ? 1.0f : 0.0f;
    return result;
}

py::array compute_signed_distance(AccelHandle& h, const py::handle& points_obj, unsigned threads, int nsamples) {
    const Rows rows = query_points(points_obj);
    const std::vector<NearestPoint> closest = closest_of(h, rows, threads);
    const std::vector<uint8_t> inside = inside_of(h, rows, threads, nsamples);
    auto result = new_array<float>(rows.lead);
    float* out = result.mutable_data();
    for (size_t i = 0; i < rows.count; ++i) out[i] = inside[i] ? -closest[i].distance : closest[i].distance;
    return result;
}

}  // namespace thicket::python
