#include "arrays.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "inputs.h"
#include "thicket/accel/accel.h"
#include "thicket/core/huge_pages.h"

namespace thicket::python {

std::string shape_text(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) {
        if (i) s += ", ";
        s += std::to_string(a.shape(i));
    }
    if (a.ndim() == 1) s += ",";
    return s + ")";
}

namespace {

std::string widths_text(std::initializer_list<size_t> widths) {
    std::string s;
    for (size_t w : widths) s += (s.empty() ? "(..., " : " or (..., ") + std::to_string(w) + ")";
    return s;
}

}  // namespace

namespace {

template <class T>
const char* dtype_name() {
    return sizeof(T) == 4 ? "float32" : "float64";
}

}  // namespace

template <class T>
RowsOf<T> typed_rows(const py::handle& obj, const char* what, std::initializer_list<size_t> widths,
                     const std::string& dtype_hint) {
    if (!py::isinstance<py::array>(obj))
        throw py::value_error(std::string(what) + ": expected a numpy " + dtype_name<T>() + " array of shape " +
                              widths_text(widths) + ", got " + std::string(py::str(py::type::of(obj).attr("__name__"))));
    py::array a = py::reinterpret_borrow<py::array>(obj);
    const std::string received = shape_text(a) + " " + std::string(py::str(a.dtype()));
    const bool width_ok = a.ndim() >= 1 && std::find(widths.begin(), widths.end(), size_t(a.shape(a.ndim() - 1))) != widths.end();
    if (!width_ok)
        throw py::value_error(std::string(what) + ": expected shape " + widths_text(widths) + ", got shape " + received);
    if (!a.dtype().is(py::dtype::of<T>()))
        throw py::value_error(std::string(what) + ": expected dtype " + dtype_name<T>() + ", got shape " + received +
                              dtype_hint);
    RowsOf<T> r;
    // Copies only a strided (or broadcast) array, its memory checked first; a C-contiguous
    // array of T is used in place.
    r.array = contiguous(a, py::dtype::of<T>(), what);
    r.width = size_t(a.shape(a.ndim() - 1));
    r.count = 1;
    for (py::ssize_t i = 0; i + 1 < a.ndim(); ++i) {
        r.lead.push_back(a.shape(i));
        r.count *= size_t(a.shape(i));
    }
    return r;
}

template Rows typed_rows<float>(const py::handle&, const char*, std::initializer_list<size_t>, const std::string&);
template RowsD typed_rows<double>(const py::handle&, const char*, std::initializer_list<size_t>, const std::string&);

Rows float32_rows(const py::handle& obj, const char* what, std::initializer_list<size_t> widths) {
    const bool rays = std::string(what) == "rays";
    return typed_rows<float>(obj, what, widths,
                             rays ? " (convert with .astype(numpy.float32); cast_rays, test_occlusions, "
                                    "count_intersections and list_intersections take float64 rays on a structure "
                                    "built with precision=double)"
                                  : " (convert with .astype(numpy.float32))");
}

void check_answer_memory(const RowsShape& rows, size_t bytes_per_row, const char* query) {
    std::string shape = "(";
    for (const py::ssize_t n : rows.lead) shape += std::to_string(n) + ", ";
    shape += std::to_string(rows.width) + ")";
    check_allocation(bytes_of(rows.count, bytes_per_row),
                     std::string(query) + ": answering an array of shape " + shape);
}

void check_interval_arguments(const RowsShape& rows, std::optional<float> tnear, std::optional<float> tfar) {
    if (rows.width == 8 && (tnear || tfar))
        throw py::value_error("rays of 8 columns carry tmin and tmax in columns 6 and 7; tnear/tfar apply only to "
                              "rays of 6 columns");
}

py::capsule huge_page_memory(size_t bytes, void*& data) {
    // Smaller arrays stay with numpy: a mapping is rounded up to whole 2 MiB pages, so below 1 MiB
    // the memory given away would exceed the array. (A 10^6-ray boolean answer, 1 MB, is above.)
    constexpr size_t kHugeArrayBytes = size_t(1) << 20;
    if (bytes < kHugeArrayBytes) return {};
    const HugeMapping mapping = take_huge_mapping(bytes);
    data = mapping.start;
    if (!data) return {};  // numpy's allocator will say why, if it fails too
    return py::capsule(new HugeMapping(mapping), [](void* p) {
        const HugeMapping* m = static_cast<HugeMapping*>(p);
        release_huge_mapping(*m);
        delete m;
    });
}

}  // namespace thicket::python
