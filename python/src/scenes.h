#pragma once
// Scenes for Python: from numpy arrays, every count bounded and its memory checked before the
// copy is made, and from files, remembering which file (by identity) so that Accel.save can
// refuse to write over it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <memory>
#include <optional>
#include <string>

#include "inputs.h"
#include "thicket/scene/loaders.h"
#include "thicket/scene/scene.h"

namespace thicket::python {

namespace py = pybind11;

/// A scene from vertices (V, 3) of any float dtype and triangles (T, 3) of any integer dtype
/// (uint64 included: an index is reported as the number it is). Every index is checked against
/// V and every coordinate must be finite (ValueError naming the row). V above 2^32 or T of 2^32 - 1
/// and more (the ids are 32-bit) is a ValueError, and a scene bigger than the memory available a
/// MemoryError naming both shapes, before anything is allocated; the arrays are read a block of
/// rows at a time, so a strided or broadcast array is never copied whole.
std::shared_ptr<Scene> scene_from_arrays(const py::array& vertices, const py::array& triangles);

/// Scene.set_vertices: moves the vertices of geometry `geometry_id` (an int in
/// 0..geometry_count-1, else ValueError naming it) to `vertices`, an array-like (numpy.asarray)
/// (N, 3) of any float dtype with N the geometry's own vertex count, every value finite as
/// float32. Every refusal is a ValueError naming the argument, and leaves the scene as it was; the
/// library's own too. The rows are converted a block at a time, as Scene(V, T) converts them.
void set_scene_vertices(Scene& scene, const py::handle& geometry_id, const py::handle& vertices);

/// load_scene(path, options) without the GIL, the scene remembering the regular file it came from.
std::shared_ptr<Scene> load_scene_file(const std::string& path, const LoadOptions& options = {});

/// The file `scene` was loaded from by load_scene_file, as it was then; nothing for a built-in
/// scene or one made from arrays.
std::optional<InputFile> scene_file(const std::shared_ptr<const Scene>& scene);

}  // namespace thicket::python
