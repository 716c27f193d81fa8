#include "scenes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "arrays.h"
#include "thicket/core/error.h"
#include "thicket/core/ray.h"

namespace thicket::python {

namespace {

/// Rows converted per block: a few MB of copy however large (or broadcast) the array is.
constexpr size_t kBlockRows = size_t(1) << 16;

/// Calls f(rows, first, count) for consecutive blocks of `a`'s rows as C-contiguous T: `a` in
/// place when it already is that, otherwise one copied block of kBlockRows at a time.
template <class T, class F>
void for_each_block(const py::array& a, const char* what, F&& f) {
    const size_t n = size_t(a.shape(0));
    const py::dtype dtype = py::dtype::of<T>();
    if (a.dtype().is(dtype) && (a.flags() & py::array::c_style) != 0) {
        f(static_cast<const T*>(a.data()), size_t(0), n);
        return;
    }
    for (size_t first = 0; first < n; first += kBlockRows) {
        const size_t end = std::min(n, first + kBlockRows);
        const py::array rows = py::reinterpret_borrow<py::array>(a[py::slice(py::ssize_t(first), py::ssize_t(end), 1)]);
        const py::array block = contiguous(rows, dtype, what);
        f(static_cast<const T*>(block.data()), first, end - first);
    }
}

/// Reads the indices of `triangles` as Index (int64_t or uint64_t, so that every value of the
/// caller's dtype is kept as it is for the message), checked against `vertex_count`.
template <class Index>
void read_indices(const py::array& triangles, size_t vertex_count, std::vector<uint32_t>& out) {
    for_each_block<Index>(triangles, "triangles", [&](const Index* rows, size_t first, size_t count) {
        for (size_t i = 0; i < 3 * count; ++i) {
            const Index index = rows[i];
            bool negative = false;
            if constexpr (std::is_signed_v<Index>) negative = index < 0;  // refused, not wrapped
            if (negative || uint64_t(index) >= vertex_count)
                throw py::value_error("triangles: row " + std::to_string(first + i / 3) + " has vertex index " +
                                      std::to_string(index) + ", outside 0.." +
                                      std::to_string(int64_t(vertex_count) - 1));
            out.push_back(uint32_t(index));
        }
    });
}

/// The deleter of a scene loaded from a file: it carries the file, for scene_file().
struct SceneSource {
    std::optional<InputFile> file;
    void operator()(Scene* scene) const { delete scene; }
};

}  // namespace

std::shared_ptr<Scene> scene_from_arrays(const py::array& vertices, const py::array& triangles) {
    if (vertices.ndim() != 2 || vertices.shape(1) != 3 || vertices.dtype().kind() != 'f')
        throw py::value_error("vertices: expected a float array of shape (V, 3), got shape " + shape_text(vertices) +
                              " " + std::string(py::str(vertices.dtype())));
    const char index_kind = triangles.dtype().kind();
    if (triangles.ndim() != 2 || triangles.shape(1) != 3 || (index_kind != 'i' && index_kind != 'u'))
        throw py::value_error("triangles: expected an integer array of shape (T, 3), got shape " +
                              shape_text(triangles) + " " + std::string(py::str(triangles.dtype())));
    const size_t nv = size_t(vertices.shape(0)), nt = size_t(triangles.shape(0));
    // Indices are 32-bit and a primitive id of 2^32 - 1 means "no primitive".
    if (nv > (size_t(1) << 32))
        throw py::value_error("vertices: " + std::to_string(nv) + " rows; 32-bit indices name at most 4294967296");
    if (nt >= size_t(kNoPrim))
        throw py::value_error("triangles: " + std::to_string(nt) + " rows; a scene holds at most " +
                              std::to_string(kNoPrim - 1) + " triangles (32-bit ids)");
    check_allocation(bytes_of(nv, sizeof(Vec3)) + bytes_of(3 * nt, sizeof(uint32_t)),
                     "Scene(vertices of shape " + shape_text(vertices) + ", triangles of shape " +
                         shape_text(triangles) + "): the scene's copy of them");
    auto scene = std::make_shared<Scene>();
    scene->name = "<arrays>";
    // Filled in place (a scene whose mesh is assigned directly is valid: Scene::runs), so that
    // the copy is made once; add_mesh would make it twice.
    std::vector<Vec3>& positions = scene->mesh.positions;
    positions.reserve(nv);
    // float64 vertices are kept as given too, for precision=double structures (float ones see
    // them rounded, as before).
    const bool keep_double = vertices.dtype().is(py::dtype::of<double>());
    if (keep_double) scene->mesh.positions_double.reserve(nv);
    for_each_block<double>(vertices, "vertices", [&](const double* rows, size_t first, size_t count) {
        for (size_t i = 0; i < count; ++i) {
            const double* p = rows + 3 * i;
            if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
                throw py::value_error("vertices: row " + std::to_string(first + i) + " is not finite");
            positions.push_back({float(p[0]), float(p[1]), float(p[2])});
            if (keep_double) scene->mesh.positions_double.push_back({p[0], p[1], p[2]});
        }
    });
    scene->mesh.indices.reserve(3 * nt);
    if (index_kind == 'u')
        read_indices<uint64_t>(triangles, nv, scene->mesh.indices);
    else
        read_indices<int64_t>(triangles, nv, scene->mesh.indices);
    return scene;
}

void set_scene_vertices(Scene& scene, const py::handle& geometry_id, const py::handle& vertices_like) {
    const size_t geometries = scene.geometry_count();
    const std::string range = geometries == 0 ? std::string("a geometry id, but the scene has no geometry")
                                              : "a geometry id in 0.." + std::to_string(geometries - 1);
    const auto id = uint32_t(int_argument(geometry_id, "geometry_id", 0, int64_t(geometries) - 1, range.c_str()));
    // numpy.asarray: a list of rows is vertices too (no copy of an array); what is not an array
    // of floats shows in the message as the shape and dtype numpy made of it.
    const py::array vertices = py::module_::import("numpy").attr("asarray")(vertices_like);
    if (vertices.ndim() != 2 || vertices.shape(1) != 3 || vertices.dtype().kind() != 'f')
        throw py::value_error("vertices: expected a float array of shape (N, 3), got shape " + shape_text(vertices) +
                              " " + std::string(py::str(vertices.dtype())));
    // Checked before the copy: a wrong count is refused without converting anything.
    const size_t want = scene.geometry(id).vertex_count, rows = size_t(vertices.shape(0));
    if (want == 0 && rows != 0)
        throw py::value_error("vertices: geometry " + std::to_string(id) + " has no vertices to move (shapes)");
    if (rows != want)
        throw py::value_error("vertices: " + std::to_string(rows) + " rows given, geometry " + std::to_string(id) +
                              " has " + std::to_string(want) +
                              " vertices (moving vertices keeps the triangles: same count, same order)");
    std::vector<Vec3> positions;
    positions.reserve(rows);
    for_each_block<double>(vertices, "vertices", [&](const double* block, size_t first, size_t count) {
        for (size_t i = 0; i < count; ++i) {
            const double* p = block + 3 * i;
            // A float64 beyond float32's range would not narrow to a number (the cast is undefined).
            for (int k = 0; k < 3; ++k)
                if (!(std::fabs(p[k]) <= double(std::numeric_limits<float>::max())))
                    throw py::value_error("vertices: row " + std::to_string(first + i) +
                                          " is not finite as float32: " + std::to_string(p[k]));
            positions.push_back({float(p[0]), float(p[1]), float(p[2])});
        }
    });
    try {
        scene.set_vertices(id, positions);
    } catch (const Error& e) {
        throw py::value_error(e.what());
    }
}

std::shared_ptr<Scene> load_scene_file(const std::string& path, const LoadOptions& options) {
    std::optional<InputFile> file = input_file(path, "the scene file");
    std::unique_ptr<Scene> scene;
    {
        py::gil_scoped_release nogil;
        scene = std::make_unique<Scene>(load_scene(path, options));
    }
    return std::shared_ptr<Scene>(scene.release(), SceneSource{std::move(file)});
}

std::optional<InputFile> scene_file(const std::shared_ptr<const Scene>& scene) {
    if (const SceneSource* source = std::get_deleter<SceneSource>(scene)) return source->file;
    return std::nullopt;
}

}  // namespace thicket::python
