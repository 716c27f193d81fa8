// thicket._thicket: scenes, structures and their queries for Python. The pure Python package
// (python/thicket/__init__.py) re-exports it; thicket.dask builds on it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <climits>
#include <cstring>
#include <memory>
#include <string>

#include "arrays.h"
#include "inputs.h"
#include "instances.h"
#include "pictures.h"
#include "queries.h"
#include "scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"

namespace py = pybind11;
using namespace py::literals;

namespace thicket::python {

namespace {

/// nsamples of the occupancy queries as an int (its odd-and-small rule is checked by the query).
int sample_count(const py::handle& nsamples) {
    return int(int_argument(nsamples, "nsamples", INT_MIN, INT_MAX, "an odd count up to 5"));
}

py::dict stats_dict(const AccelStats& s) {
    py::dict extra;
    for (const auto& [key, value] : s.extra) extra[py::str(key)] = value;
    return py::dict("spec"_a = s.spec, "primitives"_a = s.primitives, "nodes"_a = s.nodes, "leaves"_a = s.leaves,
                    "max_depth"_a = s.max_depth, "bytes"_a = s.bytes, "primitive_bytes"_a = s.primitive_bytes,
                    "sah_cost"_a = s.sah_cost, "build_ms"_a = s.build_ms, "extra"_a = extra);
}

py::list accels_list() {
    py::list out;
    for (const AccelInfo& info : accel_registry()) {
        py::list options;
        for (const OptionInfo& o : info.options) {
            py::dict d("key"_a = o.key, "help"_a = o.help, "default"_a = o.default_value);
            if (o.real) {
                d["min"] = o.real_min;
                d["max"] = o.real_max;
            } else if (o.choices.empty()) {
                d["min"] = o.min;
                d["max"] = o.max;
            } else {
                d["choices"] = o.choices;
            }
            options.append(d);
        }
        out.append(py::dict("name"_a = info.name, "summary"_a = info.summary,
                            "partitioning"_a = partitioning_name(info.partitioning), "options"_a = options,
                            "variants"_a = info.variants, "can_load"_a = bool(info.load)));
    }
    return out;
}

py::tuple bounds_tuple(const Aabb& b) {
    return py::make_tuple(py::make_tuple(b.min.x, b.min.y, b.min.z), py::make_tuple(b.max.x, b.max.y, b.max.z));
}

}  // namespace

}  // namespace thicket::python

PYBIND11_MODULE(_thicket, m) {
    using namespace thicket;
    using namespace thicket::python;
    m.doc() = "Thicket's scenes, acceleration structures and batch queries (see the thicket package)";
    // Every docstring starts with its own signature: pybind11's would show the arguments taken as
    // py::handle (to check them as the CLI does) as "handle". The types are in thicket/__init__.pyi.
    py::options options;
    options.disable_function_signatures();

    // thicket::Error -> thicket.Error (a RuntimeError); its FileError (a file missing, unreadable or
    // unwritable) -> OSError. Translators run last-registered first, so FileError is seen first.
    static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
    error.attr("__doc__") = "A RuntimeError: a bad spec, a malformed scene or saved file, a structure saved for another scene";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const FileError& e) {
            PyErr_SetString(PyExc_OSError, e.what());
        } catch (const Error& e) {
            error(e.what());
        }
    });

    py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene",
        "Triangles and shapes that structures are built over: Scene(vertices (V,3), triangles (T,3)) or load_scene(path)")
        .def(py::init(&scene_from_arrays), "vertices"_a, "triangles"_a,
             "Scene(vertices, triangles). vertices (V, 3) of any float dtype, every one finite; triangles (T, 3) of any integer dtype, every "
             "index in 0..V-1 (ValueError quoting it otherwise). V up to 2^32, T below 2^32 - 1; a scene bigger than "
             "the memory available is a MemoryError naming both shapes, before anything is allocated")
        .def_readonly("name", &Scene::name, "str: the file's name, the built-in name, or '<arrays>' for Scene(V, T)")
        .def_property_readonly("primitive_count", &Scene::primitive_count,
                               "int: triangles plus shapes (what primitive_ids number)")
        .def_property_readonly("triangle_count", [](const Scene& s) { return s.mesh.triangle_count(); },
                               "int: the triangles of the mesh (T of Scene(V, T))")
        .def_property_readonly("shape_count", [](const Scene& s) { return s.shapes.size(); },
                               "int: the analytic shapes (spheres, quadrics, ... of a JSON scene; 0 otherwise)")
        .def_property_readonly("bounds", [](const Scene& s) { return bounds_tuple(s.bounds()); },
                               "((xmin, ymin, zmin), (xmax, ymax, zmax)): the box around everything, floats")
        .def_property_readonly("vertices", [](const Scene& s) {
            auto a = new_array<float>({py::ssize_t(s.mesh.positions.size())}, {3});
            std::memcpy(a.mutable_data(), s.mesh.positions.data(), s.mesh.positions.size() * sizeof(Vec3));
            return a;
        }, "a copy of the vertex positions, float32 (V, 3)")
        .def_property_readonly("triangles", [](const Scene& s) {
            auto a = new_array<uint32_t>({py::ssize_t(s.mesh.triangle_count())}, {3});
            std::copy(s.mesh.indices.begin(), s.mesh.indices.end(), a.mutable_data());
            return a;
        }, "a copy of the triangles' vertex indices, uint32 (T, 3)")
        .def("set_vertices", &set_scene_vertices, "geometry_id"_a, "vertices"_a,
             "set_vertices(geometry_id, vertices) -> None. Moves the vertices of geometry geometry_id (int, as "
             "geometry_ids number them) to vertices, an array-like (N, 3) of any float dtype (stored as float32), N being the "
             "geometry's own vertex count, in the order they were given; its triangles keep their indices. Structures "
             "built over the scene answer for the moved scene after Accel.refit(scene) (or a rebuild). ValueError, the "
             "scene unchanged, for an id out of range, a wrong shape, dtype or count, a value not finite as float32, "
             "or a geometry of shapes. Not while a query runs on a structure over this scene in another thread")
        .def("__repr__", [](const Scene& s) {
            return "<thicket.Scene '" + s.name + "': " + std::to_string(s.mesh.triangle_count()) + " triangles, " +
                   std::to_string(s.shapes.size()) + " shapes>";
        });

    m.def("load_scene", [](const py::object& path, bool flatten) {
              LoadOptions options;
              options.flatten = flatten;
              return load_scene_file(path_argument(path, "path"), options);
          }, "path"_a, py::kw_only(), "flatten"_a = false,
          "load_scene(path, *, flatten=False) -> Scene. Loads a PLY, OBJ, glTF or JSON scene, or a built-in one ('cornell', "
          "'teapot-patches'). path: str, bytes or os.PathLike; a NUL byte in it is a ValueError. A glTF mesh that several "
          "nodes place becomes one geometry with an instance per node (Scene.instance_count); flatten=True gives one "
          "triangle soup with a copy per node instead, as before instancing");

    py::class_<AccelHandle>(m, "Accel", "An acceleration structure over a scene: thicket.build(scene, spec)")
        .def_property_readonly("spec", [](const AccelHandle& h) { return h.accel->spec(); },
                               "str: the full spec NAME:key=value,... it was built with (defaults filled in)")
        .def_property_readonly("scene", [](const AccelHandle& h) { return std::const_pointer_cast<Scene>(h.scene); },
                               "Scene: the scene it was built over, or last refitted to (kept alive with it)")
        .def_property_readonly("bounds", [](const AccelHandle& h) { return bounds_tuple(h.accel->bounds()); },
                               "((xmin, ymin, zmin), (xmax, ymax, zmax)): the box around its primitives, floats")
        .def_property_readonly("double_precision", [](const AccelHandle& h) { return h.accel->double_precision(); },
                               "bool: built with precision=double (brute, bvh): cast_rays, test_occlusions, "
                               "count_intersections and list_intersections then take float64 rays too and trace "
                               "them in double (t_hit and primitive_uvs float64)")
        .def("stats", [](const AccelHandle& h) { return stats_dict(h.accel->stats()); },
             "stats() -> dict: spec (str), primitives, nodes, leaves, max_depth, bytes, primitive_bytes (ints), "
             "sah_cost, build_ms (floats), extra (dict of the structure's own figures)")
        .def("save", [](const AccelHandle& h, const py::object& path, bool overwrite) {
            const std::string p = path_argument(path, "path");
            std::vector<InputFile> inputs;
            if (std::optional<InputFile> f = scene_file(h.scene)) inputs.push_back(*f);
            if (h.saved_from) inputs.push_back(*h.saved_from);
            refuse_clobber(p, inputs, overwrite);
            py::gil_scoped_release nogil;
            save_accel(*h.accel, *h.scene, p);
        }, "path"_a, "overwrite"_a = false,
             "save(path, overwrite=False) -> None. Saves the structure; thicket.load(path, scene) restores it for the same scene. path: str, bytes or "
             "os.PathLike. As the CLI's outputs: an existing file is replaced only with overwrite=True "
             "(FileExistsError otherwise), and the scene file the structure was built from, or the file it was "
             "loaded from, is never replaced (ValueError), under any name")
        .def("cast_rays", [](AccelHandle& h, const py::handle& rays, const py::handle& nthreads,
                             const py::handle& coherent) {
            return cast_rays(h, rays, thread_count(nthreads), bool_argument(coherent, "coherent"));
        }, "rays"_a, "nthreads"_a = 0, "coherent"_a = false,
             "cast_rays(rays, nthreads=0, coherent=False) -> dict. rays: float32 (..., 6) or (..., 8) (ox oy oz dx dy "
             "dz [tmin tmax]). Closest hit of each (Open3D's RaycastingScene.cast_rays): t_hit float32 (...) (inf on "
             "a miss), geometry_ids uint32 (...), primitive_ids uint32 (...) (INVALID_ID on a miss), primitive_uvs "
             "float32 (..., 2), primitive_normals float32 (..., 3). coherent=True: camera rays, traced in tiles (float32 rays "
             "only: refused with float64 rays, which have no packet path). nthreads: 0 (one per core) "
             "or a thread count up to 2^32 - 1, as the CLI's -j; answers that do not fit in memory are a MemoryError. "
             "float64 rays: traced in double by a structure built with precision=double (t_hit and primitive_uvs "
             "then float64), refused by the others with a ValueError naming precision=double")
        .def("test_occlusions", [](const AccelHandle& h, const py::handle& rays, const py::handle& tnear,
                                   const py::handle& tfar, const py::handle& nthreads, const py::handle& coherent) {
            return test_occlusions(h, rays, float_argument(tnear, "tnear"), float_argument(tfar, "tfar"),
                                   thread_count(nthreads), bool_argument(coherent, "coherent"));
        }, "rays"_a, "tnear"_a = py::none(), "tfar"_a = py::none(), "nthreads"_a = 0, "coherent"_a = false,
             "test_occlusions(rays, tnear=None, tfar=None, nthreads=0, coherent=False) -> bool ndarray. rays: "
             "float32 (..., 6) or (..., 8) (ox oy oz dx dy dz [tmin tmax]); answers whether anything is hit "
             "within [tnear, tfar] (floats; default the rays' own interval, else [0, inf)), bool of shape (...). "
             "float64 rays: as cast_rays (precision=double structures only). coherent=True is refused (thicket.Error): "
             "no structure traces any-hit rays in packets, so the hint would change nothing")
        .def("count_intersections", [](const AccelHandle& h, const py::handle& rays, const py::handle& nthreads) {
            return count_intersections(h, rays, thread_count(nthreads));
        }, "rays"_a, "nthreads"_a = 0,
             "count_intersections(rays, nthreads=0) -> int32 ndarray. rays: float32 (..., 6) or (..., 8). "
             "Number of surface crossings of each ray, int32 (...) (a shared edge or vertex "
             "crossed once counts once). float64 rays: crossings found in double by a structure built with "
             "precision=double, refused by the others with a ValueError naming precision=double")
        .def("list_intersections", [](const AccelHandle& h, const py::handle& rays, const py::handle& nthreads) {
            return list_intersections(h, rays, thread_count(nthreads));
        }, "rays"_a, "nthreads"_a = 0,
             "list_intersections(rays, nthreads=0) -> dict. rays: float32 (..., 6) or (..., 8), N of them taken in "
             "row order. Every crossing, sorted by t per ray (Open3D 0.17's layout): ray_splits uint32 (N + 1,) "
             "(ray i's crossings are [ray_splits[i], ray_splits[i + 1])), ray_ids uint32 (M,), t_hit float32 (M,), "
             "geometry_ids uint32 (M,), primitive_ids uint32 (M,), primitive_uvs float32 (M, 2). float64 rays: as "
             "count_intersections (precision=double structures only; t_hit and primitive_uvs then float64)")
        .def("compute_closest_points", [](AccelHandle& h, const py::handle& points, const py::handle& nthreads) {
            return compute_closest_points(h, points, thread_count(nthreads));
        }, "query_points"_a, "nthreads"_a = 0,
             "compute_closest_points(query_points, nthreads=0) -> dict. query_points: float32 (..., 3). The closest "
             "surface point of each: points float32 (..., 3), geometry_ids uint32 (...), primitive_ids uint32 (...), "
             "primitive_uvs float32 (..., 2), primitive_normals float32 (..., 3) (triangle scenes). float64 points "
             "are refused on every structure (point queries are computed in float32, precision=double included)")
        .def("compute_distance", [](AccelHandle& h, const py::handle& points, const py::handle& nthreads) {
            return compute_distance(h, points, thread_count(nthreads));
        }, "query_points"_a, "nthreads"_a = 0,
             "compute_distance(query_points, nthreads=0) -> float32 ndarray. query_points: float32 (..., 3). "
             "Distance to the surface, float32 (...)")
        .def("compute_signed_distance", [](AccelHandle& h, const py::handle& points, const py::handle& nthreads,
                                           const py::handle& nsamples) {
            return compute_signed_distance(h, points, thread_count(nthreads), sample_count(nsamples));
        }, "query_points"_a, "nthreads"_a = 0, "nsamples"_a = 1,
             "compute_signed_distance(query_points, nthreads=0, nsamples=1) -> float32 ndarray. query_points: "
             "float32 (..., 3). Distance to the surface, negative inside (by compute_occupancy), float32 (...)")
        .def("compute_occupancy", [](const AccelHandle& h, const py::handle& points, const py::handle& nthreads,
                                     const py::handle& nsamples) {
            return compute_occupancy(h, points, thread_count(nthreads), sample_count(nsamples));
        }, "query_points"_a, "nthreads"_a = 0, "nsamples"_a = 1,
             "compute_occupancy(query_points, nthreads=0, nsamples=1) -> float32 ndarray. query_points: float32 "
             "(..., 3). 1 inside, 0 outside, float32 (...), by the parity of crossings along nsamples (odd, up to 5) "
             "directions, the majority deciding")
        .def("refit", [](AccelHandle& h, std::shared_ptr<Scene> scene, const py::handle& nthreads) {
            if (!scene) throw py::value_error("refit: scene is None");
            const unsigned threads = thread_count(nthreads);
            {
                py::gil_scoped_release nogil;
                h.accel->refit(*scene, threads);
            }
            // What the handle derived from the old positions goes with them: the normals cast_rays
            // caches, and the bvh8 closest points may have built for a structure that cannot answer
            // them itself (PointQueries also holds the scene it was made for).
            h.scene = scene;
            h.triangle_normals.reset();
            h.points = std::make_unique<PointQueries>(*h.accel, *h.scene);
        }, "scene"_a, "nthreads"_a = 0,
             "refit(scene, nthreads=0) -> None. Brings the structure up to date with scene after Scene.set_vertices "
             "moved its vertices: scene must have the primitives the structure was built over, in the same order "
             "(only positions may differ); it becomes the structure's scene. The tree keeps its shape and its boxes "
             "are recomputed, so every query then answers for the moved scene (exactly as a rebuild would), though "
             "perhaps slower than after a rebuild. bvh, bvh8 and obb refit (see refittable); others raise "
             "thicket.Error saying to rebuild, as does a scene of another topology, leaving the structure unchanged. "
             "Runs without the GIL on nthreads threads (0: one per core); not while a query runs on this structure "
             "in another thread")
        .def_property_readonly("refittable", [](const AccelHandle& h) { return h.accel->refittable(); },
                               "bool: whether refit() is supported (bvh, bvh8, obb)")
        .def("__repr__", [](const AccelHandle& h) { return "<thicket.Accel '" + h.accel->spec() + "'>"; });

    m.def("build", [](std::shared_ptr<Scene> scene, const std::string& spec) {
        if (!scene) throw py::value_error("build: scene is None");
        check_no_nul(spec, "spec");
        py::gil_scoped_release nogil;
        std::shared_ptr<Accel> accel = build_accel(spec, *scene);
        return AccelHandle(scene, accel);
    }, "scene"_a, "spec"_a = kDefaultSpec,
          "build(scene, spec='bvh8') -> Accel. Builds a structure over scene (a Scene) from a spec string "
          "NAME[:key=value,...] (see accels()); thicket.Error for a bad spec");

    m.def("load", [](const py::object& path, std::shared_ptr<Scene> scene) {
        if (!scene) throw py::value_error("load: scene is None");
        const std::string p = path_argument(path, "path");
        std::optional<InputFile> file = input_file(p, "the saved structure");
        std::shared_ptr<Accel> accel;
        {
            py::gil_scoped_release nogil;
            accel = load_accel(p, *scene);
        }
        AccelHandle handle(scene, accel);
        handle.saved_from = std::move(file);
        return handle;
    }, "path"_a, "scene"_a,
          "load(path, scene) -> Accel. Loads a structure saved by Accel.save for the same scene (path: str, bytes "
          "or os.PathLike); thicket.Error when the file was saved for another scene");

    m.attr("DEFAULT_SPEC") = kDefaultSpec;  // what build() and RaycastingScene take without a spec
    m.def("accels", &accels_list,
          "accels() -> list of dict. Every registered structure: name, summary, partitioning (str), options (list of "
          "dict: key, help, default, and min/max or choices), variants (list of str), can_load (bool)");
    m.def("_batch_seconds", [](AccelHandle& h, const py::handle& rows, const std::string& query, const py::handle& nthreads) {
        return batch_seconds(h, rows, query, thread_count(nthreads));
    }, "accel"_a, "rows"_a, "query"_a, "nthreads"_a = 0,
          "_batch_seconds(accel, rows, query, nthreads=0) -> float. For python/bench/module_bench.py: seconds of the C++ batch call alone (closest, any, count, closest_point)");

    add_picture_functions(m);  // Accel.render among them: after Accel
    add_instance_functions(m);  // on Scene and Accel: after both
}
