// Two-level instancing for Python: Scene.add_instance and Scene.add_geometry, and on a structure
// built over a scene with instances (an InstancedAccel), Accel.set_transform and Accel.locate.
// thicket.RaycastingScene's add_instance and set_transform are made of these.
#include "instances.h"

#include <pybind11/numpy.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "arrays.h"
#include "inputs.h"
#include "queries.h"
#include "thicket/instances/instances.h"
#include "thicket/core/error.h"
#include "thicket/scene/instance.h"
#include "thicket/scene/scene.h"

namespace thicket::python {

using namespace py::literals;

namespace {

/// `value` (an array-like of shape (3, 4) or (4, 4), any real dtype) as an Affine. ValueError
/// naming `what` for another shape, a non-finite entry or a 4x4 whose last row is not 0 0 0 1 (a
/// projective map, which no affine instance can stand for).
Affine affine_argument(const py::handle& value, const char* what) {
    const py::array a = py::module_::import("numpy").attr("asarray")(value);
    const char kind = a.dtype().kind();
    if (a.ndim() != 2 || (a.shape(0) != 3 && a.shape(0) != 4) || a.shape(1) != 4 ||
        (kind != 'f' && kind != 'i' && kind != 'u'))
        throw py::value_error(std::string(what) + ": expected a (3, 4) or (4, 4) array of numbers, got shape " +
                              shape_text(a) + " " + std::string(py::str(a.dtype())));
    const py::array m = contiguous(a, py::dtype::of<double>(), what);
    const double* v = static_cast<const double*>(m.data());
    for (int i = 0; i < int(a.shape(0)) * 4; ++i)
        if (!std::isfinite(v[i]))
            throw py::value_error(std::string(what) + ": entry [" + std::to_string(i / 4) + ", " +
                                  std::to_string(i % 4) + "] is not finite: " + std::to_string(v[i]));
    if (a.shape(0) == 4 && (v[12] != 0 || v[13] != 0 || v[14] != 0 || v[15] != 1))
        throw py::value_error(std::string(what) + ": the last row of a 4x4 transform must be [0, 0, 0, 1] (an affine "
                              "map), got [" + std::to_string(v[12]) + ", " + std::to_string(v[13]) + ", " +
                              std::to_string(v[14]) + ", " + std::to_string(v[15]) + "]");
    Affine t;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) {
            const double x = v[4 * r + c];
            if (!(std::fabs(x) <= double(std::numeric_limits<float>::max())))
                throw py::value_error(std::string(what) + ": entry [" + std::to_string(r) + ", " + std::to_string(c) +
                                      "] is not finite as float32: " + std::to_string(x));
            t.m[r][c] = float(x);
        }
    return t;
}

/// The instanced structure behind `h`; thicket.Error for one built over a scene without instances.
InstancedAccel& instanced(AccelHandle& h, const char* call) {
    auto* accel = dynamic_cast<InstancedAccel*>(h.accel.get());
    if (!accel)
        throw Error(std::string(call) + ": the structure '" + h.accel->spec() +
                    "' was built over a scene without instances (Scene.add_instance before thicket.build)");
    return *accel;
}

}  // namespace

void add_instance_functions(py::module_& m) {
    auto scene_class = py::reinterpret_borrow<py::class_<Scene, std::shared_ptr<Scene>>>(m.attr("Scene"));
    auto accel_class = py::reinterpret_borrow<py::class_<AccelHandle>>(m.attr("Accel"));

    scene_class
        .def("add_geometry", [](Scene& scene, const Scene& other) {
            if (other.has_shapes() || !other.instances.empty())
                throw py::value_error("add_geometry: the scene '" + other.name + "' has shapes or instances; only a "
                                      "scene of triangles (Scene(vertices, triangles)) can be added");
            return scene.add_mesh(other.mesh);
        }, "other"_a,
             "add_geometry(other) -> int. Appends the triangles of other (a Scene of triangles) as a new geometry "
             "of this scene, its primitives the next ids; returns the geometry's id (what Scene.add_instance takes)")
        .def("add_instance", [](Scene& scene, const py::handle& geometry_id, const py::handle& transform) {
            const int64_t count = int64_t(scene.geometry_count());
            const std::string rule = count == 0 ? std::string("a geometry id, but the scene has no geometry")
                                                : "a geometry id in 0.." + std::to_string(count - 1);
            const auto id = uint32_t(int_argument(geometry_id, "geometry_id", 0, count - 1, rule.c_str()));
            return scene.add_instance(id, affine_argument(transform, "transform"));
        }, "geometry_id"_a, "transform"_a,
             "add_instance(geometry_id, transform) -> int. Places geometry geometry_id again under transform (object "
             "to world), a (3, 4) or (4, 4) array-like (its last row 0 0 0 1), and returns the instance's id (0, 1, "
             "...). Once a scene has an instance, its geometries are prototypes, drawn only where instances place "
             "them, and thicket.build makes a two-level structure whose primitive_ids are flattened ids "
             "(Accel.locate). ValueError for an id out of range, a bad shape, a non-finite entry or a bad last row; "
             "thicket.Error for a near-singular transform (condition number above 1e4)")
        .def_property_readonly("instance_count", [](const Scene& s) { return s.instances.size(); },
                               "int: the instances (Scene.add_instance; 0 for a scene drawn as it is)");

    accel_class
        .def("set_transform", [](AccelHandle& h, const py::handle& instance_id, const py::handle& transform) {
            InstancedAccel& accel = instanced(h, "set_transform");
            const int64_t count = int64_t(accel.instances().size());
            const std::string rule = "an instance id in 0.." + std::to_string(count - 1);
            const auto id = uint32_t(int_argument(instance_id, "instance_id", 0, count - 1, rule.c_str()));
            const Affine t = affine_argument(transform, "transform");
            accel.set_transform(id, t);  // throws, nothing changed, for a near-singular one
            // The scene's copy moves too: the normals of hits (Scene::normal) are carried to the
            // world by the scene's instances. It is the scene this structure was built over.
            const_cast<Scene&>(*h.scene).instances.at(id).transform = t;
        }, "instance_id"_a, "transform"_a,
             "set_transform(instance_id, transform) -> None. Moves instance instance_id of a structure built over a "
             "scene with instances to transform ((3, 4) or (4, 4), as Scene.add_instance takes it), rebuilding only "
             "the top level; the scene's instance moves with it (other structures over that scene do not: build "
             "them again). thicket.Error for a structure without instances or a near-singular transform; "
             "ValueError for an id out of range or a bad transform; nothing changes on error")
        .def("locate", [](AccelHandle& h, const py::handle& primitive_ids) {
            const InstancedAccel& accel = instanced(h, "locate");
            const py::array given = py::module_::import("numpy").attr("asarray")(primitive_ids);
            const char kind = given.dtype().kind();
            if (kind != 'i' && kind != 'u')
                throw py::value_error("primitive_ids: expected an integer array, got " +
                                      std::string(py::str(given.dtype())));
            // Read wide, so that a negative id or one past 32 bits is refused, not wrapped.
            const py::array wide = contiguous(given, py::dtype::of<int64_t>(), "primitive_ids");
            const auto* ids = static_cast<const int64_t*>(wide.data());
            for (py::ssize_t k = 0; k < wide.size(); ++k)
                if (ids[k] < 0 || ids[k] > int64_t(kNoPrim))
                    throw py::value_error("primitive_ids: entry " + std::to_string(k) + " is " + std::to_string(ids[k]) +
                                          ", not a primitive id (0..4294967295, the last a miss's)");
            const py::array flat = contiguous(wide, py::dtype::of<uint32_t>(), "primitive_ids");
            std::vector<py::ssize_t> shape(flat.shape(), flat.shape() + flat.ndim());
            py::array_t<uint32_t> instance(shape), geometry(shape), prim(shape);
            const auto* in = static_cast<const uint32_t*>(flat.data());
            uint32_t* out_i = instance.mutable_data();
            uint32_t* out_g = geometry.mutable_data();
            uint32_t* out_p = prim.mutable_data();
            const size_t n = size_t(flat.size());
            {
                py::gil_scoped_release nogil;
                for (size_t k = 0; k < n; ++k) {
                    const InstanceHit where = accel.locate(in[k]);  // a miss's id: all kNoPrim
                    out_i[k] = where.instance;
                    out_g[k] = where.geometry;
                    out_p[k] = where.prim;
                }
            }
            return py::dict("instance_ids"_a = instance, "geometry_ids"_a = geometry, "primitive_ids"_a = prim);
        }, "primitive_ids"_a,
             "locate(primitive_ids) -> dict. What the flattened primitive ids of a structure with instances (its "
             "answers' primitive_ids) stand for, uint32 arrays of the same shape: instance_ids, geometry_ids (the "
             "prototype's geometry) and primitive_ids (within that geometry); 4294967295 in all three for a miss's "
             "id or one past the instanced primitives. thicket.Error for a structure without instances")
        .def_property_readonly("instance_count", [](AccelHandle& h) -> size_t {
            auto* accel = dynamic_cast<const InstancedAccel*>(h.accel.get());
            return accel ? accel->instances().size() : 0;
        }, "int: the instances of a two-level structure (0 for a structure over a scene without instances)");
}

}  // namespace thicket::python
