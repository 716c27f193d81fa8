#pragma once
// The queries of thicket.Accel, numpy in and out, named and shaped as Open3D 0.16's
// RaycastingScene answers them. Each releases the GIL while it converts and traces, and traces
// through the library's batch API (all cores unless nthreads says otherwise), one chunk of
// kBatchGrain rows at a time: each thread converts its chunk's rows, traces them and writes the
// answers into the output arrays, so the module adds no pass over the batch of its own.
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "arrays.h"
#include "inputs.h"
#include "thicket/accel/accel.h"
#include "thicket/query/point_queries.h"
#include "thicket/scene/scene.h"

namespace thicket::python {

/// A structure and the scene it was built over, or last refitted to (normals and closest points
/// need the scene; the structure must not outlive it).
struct AccelHandle {
    AccelHandle(std::shared_ptr<const Scene> s, std::shared_ptr<Accel> a)
        : scene(std::move(s)), accel(std::move(a)), points(std::make_unique<PointQueries>(*accel, *scene)) {}
    std::shared_ptr<const Scene> scene;
    /// Not const: Accel.refit updates it in place.
    std::shared_ptr<Accel> accel;
    /// The library's point queries over both (closest points from a bvh8 built on first use when
    /// `accel` cannot answer them itself).
    std::unique_ptr<PointQueries> points;
    /// Scene::normal of every triangle of a triangle scene, made on its first cast_rays and dropped
    /// by Accel.refit (only ever touched with the GIL held): cast_rays writes one normal per hit,
    /// and one load from here costs a sixth of the index and vertex loads (and the square root) behind Scene::normal.
    std::shared_ptr<const std::vector<Vec3>> triangle_normals;
    /// The saved structure it was loaded from (thicket.load), which Accel.save never replaces.
    std::optional<InputFile> saved_from;
};

/// A dict of the named answers, in order: what every query that answers several arrays returns.
inline py::dict named_answers(std::initializer_list<std::pair<const char*, py::object>> answers) {
    py::dict out;
    for (const auto& [name, value] : answers) out[name] = value;
    return out;
}

/// cast_rays' five arrays over the rays' leading shape, t_hit and primitive_uvs as `Real`
/// (float32 for float rays, float64 for float64 ones), allocated untouched: the threads that
/// write a chunk's answers take its pages' first-touch faults, in parallel with the tracing.
template <class Real>
struct CastArrays {
    explicit CastArrays(const std::vector<py::ssize_t>& lead)
        : t_hit(new_array<Real>(lead)),
          geometry_ids(new_array<uint32_t>(lead)),
          primitive_ids(new_array<uint32_t>(lead)),
          uvs(new_array<Real>(lead, {2})),
          normals(new_array<float>(lead, {3})) {}
    py::array_t<Real> t_hit;
    py::array_t<uint32_t> geometry_ids, primitive_ids;
    py::array_t<Real> uvs;
    py::array_t<float> normals;

    /// The dict cast_rays returns, Open3D's keys.
    py::dict answer() const {
        return named_answers({{"t_hit", t_hit}, {"geometry_ids", geometry_ids}, {"primitive_ids", primitive_ids},
                              {"primitive_uvs", uvs}, {"primitive_normals", normals}});
    }
};

/// Open3D's cast_rays: dict of t_hit (inf on a miss), geometry_ids (0, or 4294967295 on a miss),
/// primitive_ids (4294967295 on a miss), primitive_uvs (..., 2), primitive_normals (..., 3).
py::dict cast_rays(AccelHandle& h, const py::handle& rays, unsigned threads, bool coherent);

/// Open3D's test_occlusions: a bool array of the rays' leading shape.
py::array test_occlusions(const AccelHandle& h, const py::handle& rays, std::optional<float> tnear,
                          std::optional<float> tfar, unsigned threads, bool coherent);


/// Open3D's count_intersections: int32 array of the rays' leading shape; a crossing through an
/// edge or vertex shared by several triangles counts once (Accel::all_hits).
py::array count_intersections(const AccelHandle& h, const py::handle& rays, unsigned threads);

/// Open3D 0.17's list_intersections over the rays taken in row order: dict of ray_splits (uint32,
/// rays + 1), ray_ids, t_hit, geometry_ids, primitive_ids, primitive_uvs, sorted by t per ray.
py::dict list_intersections(const AccelHandle& h, const py::handle& rays, unsigned threads);

/// list_intersections' dict from `lists` (HitLists or HitListsD: splits per ray, hits in ray order)
/// over `rays` rays of `scene`: ray_splits, ray_ids, t_hit, geometry_ids, primitive_ids and
/// primitive_uvs, t and uv as `Real` (float32 for float rays, float64 for float64 ones).
template <class Real, class Lists>
py::dict intersection_lists_answer(const Scene& scene, const Lists& lists, size_t rays) {
    const size_t n = lists.hits.size();
    auto splits = new_array<uint32_t>({py::ssize_t(rays + 1)});
    auto ray_ids = new_array<uint32_t>({py::ssize_t(n)});
    auto t_hit = new_array<Real>({py::ssize_t(n)});
    auto geometry_ids = new_array<uint32_t>({py::ssize_t(n)});
    auto primitive_ids = new_array<uint32_t>({py::ssize_t(n)});
    auto uvs = new_array<Real>({py::ssize_t(n)}, {2});
    uint32_t* sp = splits.mutable_data();
    uint32_t* ids = ray_ids.mutable_data();
    Real* t = t_hit.mutable_data();
    uint32_t* geom = geometry_ids.mutable_data();
    uint32_t* prim = primitive_ids.mutable_data();
    Real* uv = uvs.mutable_data();
    {
        py::gil_scoped_release nogil;
        for (size_t row = 0; row <= rays; ++row) sp[row] = uint32_t(lists.splits[row]);
        for (size_t row = 0; row < rays; ++row)
            for (size_t j = lists.splits[row]; j < lists.splits[row + 1]; ++j) {
                const auto& hit = lists.hits[j];
                ids[j] = uint32_t(row);
                t[j] = hit.t;
                geom[j] = scene.geometry_of(hit.prim);
                prim[j] = hit.prim;
                uv[2 * j] = hit.u;
                uv[2 * j + 1] = hit.v;
            }
    }
    return named_answers({{"ray_splits", splits}, {"ray_ids", ray_ids}, {"t_hit", t_hit},
                          {"geometry_ids", geometry_ids}, {"primitive_ids", primitive_ids}, {"primitive_uvs", uvs}});
}

/// Open3D's compute_closest_points for points (..., 3): dict of points, geometry_ids,
/// primitive_ids, primitive_uvs, primitive_normals. Structures that cannot answer closest points
/// themselves use a bvh8 built over the same scene on first use.
py::dict compute_closest_points(AccelHandle& h, const py::handle& points, unsigned threads);
/// Distance to the surface, float32 of the points' leading shape.
py::array compute_distance(AccelHandle& h, const py::handle& points, unsigned threads);
/// Inside (1) or outside (0) by the parity of crossings along `nsamples` fixed directions, the
/// majority deciding (Open3D: float32).
py::array compute_occupancy(const AccelHandle& h, const py::handle& points, unsigned threads, int nsamples);
/// compute_distance, negative where compute_occupancy says inside.
py::array compute_signed_distance(AccelHandle& h, const py::handle& points, unsigned threads, int nsamples);

/// For python/bench/module_bench.py, not the API: the seconds the C++ batch call alone takes for
/// `query` ("closest", "any", "count" over rays (N, 8), "closest_point" over points (N, 3)) with
/// the rows converted and the answers' vector allocated and touched beforehand, as `thicket trace`
/// and `thicket closest` time it, in this process, so that the module's figure can be set against
/// it call for call on the same structure.
double batch_seconds(AccelHandle& h, const py::handle& rows, const std::string& query, unsigned threads);

}  // namespace thicket::python
