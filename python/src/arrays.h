#pragma once
// numpy arrays in and out of the module: shape and dtype checks that name what was received, the
// rows handed to the library's ray conversion (query/ray_rows.h), and output arrays that keep the input's leading shape.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/query/ray_rows.h"
#include "thicket/core/ray.h"

namespace thicket::python {

namespace py = pybind11;

/// A C-contiguous array of rows: `lead` is its shape without the last axis, `width` the last
/// axis, `count` the number of rows (the product of `lead`). Holding `array` keeps the data valid.
struct RowsShape {
    py::array array;
    std::vector<py::ssize_t> lead;
    size_t width = 0;
    size_t count = 0;
};

/// Rows of T (float: float32 rays and points; double: float64 rays for precision=double).
template <class T>
struct RowsOf : RowsShape {
    const T* data() const { return static_cast<const T*>(array.data()); }
};
using Rows = RowsOf<float>;
using RowsD = RowsOf<double>;

/// "(3, 7)": a shape as Python prints it.
std::string shape_text(const py::array& a);

/// `obj` as rows of T (float32 or float64) whose last axis is one of `widths`; anything else is a
/// ValueError naming `what`, the shape and dtype received and what is expected, `dtype_hint`
/// added to a wrong dtype's message (what to do instead). Never converts dtypes silently.
/// Copies only when the array is not C-contiguous (its memory checked first).
template <class T>
RowsOf<T> typed_rows(const py::handle& obj, const char* what, std::initializer_list<size_t> widths,
                     const std::string& dtype_hint);

/// typed_rows<float>: a float64 array is refused (as Open3D does), the message saying to convert
/// with .astype(numpy.float32) and, for rays, which structures take float64 ones.
Rows float32_rows(const py::handle& obj, const char* what, std::initializer_list<size_t> widths);

/// The rows as the library reads them (query/ray_rows.h): rows of 6 take [tnear, tfar] as every
/// ray's interval, rows of 8 carry their own.
inline RayRows ray_rows(const Rows& rows, float tnear = 0.0f, float tfar = kInfinity) {
    return RayRows{rows.data(), rows.count, rows.width, tnear, tfar};
}

/// The library's batch options for a query on `threads` threads (0: every core), the rest default.
inline BatchOptions on_threads(unsigned threads) {
    BatchOptions options;
    options.threads = threads;
    return options;
}

/// MemoryError "<query>: answering an array of shape (...) needs ..." unless `bytes_per_row`
/// for every row of `rows` fits in the memory available (check_allocation): called before a
/// query allocates its output arrays.
void check_answer_memory(const RowsShape& rows, size_t bytes_per_row, const char* query);

/// tnear/tfar of the 6-column form; with 8 columns the row holds the interval and giving them too
/// is a ValueError (which one would win is not obvious).
void check_interval_arguments(const RowsShape& rows, std::optional<float> tnear, std::optional<float> tfar);

/// Memory for an output array of `bytes`, or an empty handle for numpy's own allocator: an array
/// of 1 MiB and more gets a mapping of its own on 2 MiB pages (take_huge_mapping, core/huge_pages.h),
/// which the capsule returned hands back to the pool when the array dies. Writing a batch's answers
/// into fresh memory faults every page in; on 4 KiB pages (numpy's malloc leaves most of a 4 MiB
/// array on them) those faults cost more than converting the rows (BENCHMARKS.md, "The module
/// against the C++ batch API"), on 2 MiB pages one fault in 512, and a kept
/// mapping none. `data` receives the memory; its contents are undefined (every query writes every
/// element).
py::capsule huge_page_memory(size_t bytes, void*& data);

/// A new C-contiguous array of shape lead + tail, its memory untouched (the threads that write
/// the answers fault it in, in parallel), on huge pages when it is large (huge_page_memory).
template <class T>
py::array_t<T> new_array(const std::vector<py::ssize_t>& lead, std::initializer_list<py::ssize_t> tail = {}) {
    std::vector<py::ssize_t> shape = lead;
    shape.insert(shape.end(), tail.begin(), tail.end());
    size_t count = 1;
    for (py::ssize_t n : shape) count *= size_t(n);
    void* data = nullptr;
    if (py::capsule owner = huge_page_memory(count * sizeof(T), data))
        return py::array_t<T>(shape, static_cast<T*>(data), owner);
    return py::array_t<T>(shape);
}

}  // namespace thicket::python
