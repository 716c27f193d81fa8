#pragma once
// Two-level instancing in the Python module (instances.cpp).
#include <pybind11/pybind11.h>

namespace thicket::python {

namespace py = pybind11;

/// Adds Scene.add_geometry, Scene.add_instance, Scene.instance_count and Accel.set_transform,
/// Accel.locate, Accel.instance_count to the module's classes (call after both are defined).
void add_instance_functions(py::module_& m);

}  // namespace thicket::python
