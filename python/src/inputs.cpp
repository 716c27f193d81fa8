#include "inputs.h"

#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <system_error>

#include "thicket/core/error.h"
#include "thicket/util/input_file.h"

namespace thicket::python {

namespace {

/// `text` quoted, its control and non-ASCII bytes as \xNN, so that a NUL shows where it is.
std::string quoted(const std::string& text) {
    std::string s = "'";
    for (const char c : text) {
        const auto b = static_cast<unsigned char>(c);
        if (b >= 0x20 && b < 0x7f && c != '\'' && c != '\\') {
            s += c;
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", b);
            s += buf;
        }
    }
    return s + "'";
}

}  // namespace

void check_no_nul(const std::string& text, const char* what) {
    const size_t at = text.find('\0');
    if (at != std::string::npos)
        throw py::value_error(std::string(what) + " contains a NUL byte at position " + std::to_string(at) + ": " +
                              quoted(text));
}

std::string path_argument(const py::handle& path, const char* what) {
    // os.fsencode takes str, bytes and os.PathLike alike and gives the bytes the file system
    // sees: a bytes path stays those bytes (not "b'x.bin'"), and a str path that os.fsdecode made
    // from undecodable bytes gets them back, where encoding it as UTF-8 would fail.
    const py::bytes encoded = py::module_::import("os").attr("fsencode")(path);
    std::string p = encoded;
    check_no_nul(p, what);
    return p;
}

int64_t int_argument(const py::handle& value, const char* what, int64_t lo, int64_t hi, const char* rule) {
    // An int subclass (bool, numpy's integers through __index__) counts; a float does not, as
    // range() refuses it too.
    if (!PyIndex_Check(value.ptr()))
        throw py::type_error(std::string(what) + " must be an integer, got " +
                             std::string(py::str(py::type::of(value).attr("__name__"))));
    const py::int_ number = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
    if (!number) throw py::error_already_set();
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(number.ptr(), &overflow);
    if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
    if (overflow != 0 || v < lo || v > hi)
        throw py::value_error(std::string(what) + " must be " + rule + ", got " + std::string(py::str(py::handle(number))));
    return v;
}

bool bool_argument(const py::handle& value, const char* what) {
    if (value.ptr() == Py_True || value.ptr() == Py_False) return value.ptr() == Py_True;
    if (py::isinstance(value, py::module_::import("numpy").attr("bool_"))) return PyObject_IsTrue(value.ptr()) == 1;
    throw py::type_error(std::string(what) + " must be True or False, got " +
                         std::string(py::str(py::type::of(value).attr("__name__"))));
}

std::optional<float> float_argument(const py::handle& value, const char* what) {
    if (value.is_none()) return std::nullopt;
    // A str would convert ("1.5"); a number of any kind is what is meant.
    if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr()) || !PyNumber_Check(value.ptr()))
        throw py::type_error(std::string(what) + " must be a number or None, got " +
                             std::string(py::str(py::type::of(value).attr("__name__"))));
    const double v = PyFloat_AsDouble(value.ptr());
    if (v == -1.0 && PyErr_Occurred()) throw py::error_already_set();
    return float(v);
}

unsigned thread_count(const py::handle& nthreads) {
    return unsigned(int_argument(nthreads, "nthreads", 0, std::numeric_limits<unsigned>::max(),
                                 "0 (one thread per core) or a thread count up to 4294967295"));
}

uint64_t bytes_of(uint64_t count, uint64_t size) {
    uint64_t bytes = 0;
    return __builtin_mul_overflow(count, size, &bytes) ? std::numeric_limits<uint64_t>::max() : bytes;
}

void check_allocation(uint64_t bytes, const std::string& what) {
    try {
        check_memory(bytes, what);
    } catch (const Error& e) {
        PyErr_SetString(PyExc_MemoryError, e.what());
        throw py::error_already_set();
    }
}

py::array contiguous(const py::array& a, const py::dtype& dtype, const char* what) {
    if (a.dtype().is(dtype) && (a.flags() & py::array::c_style) != 0) return a;
    uint64_t count = 1;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) count = bytes_of(count, uint64_t(a.shape(i)));
    std::string shape = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
    shape += a.ndim() == 1 ? ",)" : ")";
    check_allocation(bytes_of(count, uint64_t(dtype.itemsize())),
                     std::string(what) + ": a contiguous " + std::string(py::str(py::handle(dtype))) + " copy of the array of shape " + shape);
    // Through numpy itself rather than pybind11's array_t::ensure, which clears the error it
    // fails with (a MemoryError would become "error_already_set called while Python error
    // indicator not set").
    return py::module_::import("numpy").attr("ascontiguousarray")(a, dtype);
}

std::optional<InputFile> input_file(const std::string& path, const char* role) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
    return InputFile{role, path, st.st_dev, st.st_ino};
}

void refuse_clobber(const std::string& path, const std::vector<InputFile>& inputs, bool overwrite) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return;  // a new file (or one the writer will report on)
    for (const InputFile& in : inputs) {
        std::error_code ec;
        // The file the input was read from, or whatever now stands at the input's path.
        const bool same = (st.st_dev == in.device && st.st_ino == in.inode) ||
                          (std::filesystem::equivalent(path, in.path, ec) && !ec);
        if (same)
            throw py::value_error(path + " is " + in.role + " " + in.path + " this structure was made from: " +
                                  "saving there would destroy it; choose another path");
    }
    if (S_ISREG(st.st_mode) && !overwrite) {
        PyErr_SetString(PyExc_FileExistsError, (path + " already exists (pass overwrite=True to replace it)").c_str());
        throw py::error_already_set();
    }
}

}  // namespace thicket::python
