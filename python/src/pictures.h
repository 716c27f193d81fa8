#pragma once
// Rays and pictures for Python: the bench's ray sets (thicket.rays), the preview views' answers
// as arrays (Accel.render), the path tracer's radiance (thicket.path_trace) and PNG output
// (thicket.save_png, thicket.heat_colours). Each is the library's own code (bench/ray_sets.h,
// render/view_buffers.h, render/integrator.h, render/image.h), run without the GIL.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>

#include "queries.h"
#include "thicket/scene/scene.h"

namespace thicket::python {

namespace py = pybind11;

/// Registers rays, path_trace, heat_colours and save_png on `m`, and render on its Accel class
/// (call after Accel is defined).
void add_picture_functions(py::module_& m);

}  // namespace thicket::python
