#pragma once
// The module's arguments checked as the CLI checks its own: paths (str, bytes or os.PathLike),
// strings without NUL bytes, integer counts in range, memory for what a caller's sizes ask for
// before it is allocated, and outputs that would replace an existing file or one of the inputs.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace thicket::python {

namespace py = pybind11;

/// A file an object was read from, as it was when read: its path and its identity (device and
/// inode), so that a later output can be recognised as the same file under another name.
struct InputFile {
    std::string role;  ///< "the scene file", "the saved structure": for messages
    std::string path;
    dev_t device = 0;
    ino_t inode = 0;
};

/// `path` (str, bytes or os.PathLike) as a str path: bytes are decoded with os.fsdecode, as
/// open() does. A path containing a NUL byte is a ValueError naming `what` and the position;
/// anything that is not a path is os.fspath's TypeError.
std::string path_argument(const py::handle& path, const char* what);

/// Throws ValueError "<what> contains a NUL byte at position k: '...'" when `text` has one (the
/// library's messages are C strings, which would cut the text there).
void check_no_nul(const std::string& text, const char* what);

/// `value` as an integer in [lo, hi]: a ValueError "<what> must be ..., got <value>" for an int
/// out of range (however large) and a TypeError for a non-integer; never pybind's "incompatible
/// function arguments" listing every argument (the rays included).
int64_t int_argument(const py::handle& value, const char* what, int64_t lo, int64_t hi, const char* rule);

/// True or False (numpy's bool_ too); anything else is a TypeError naming `what`.
bool bool_argument(const py::handle& value, const char* what);

/// None (nothing) or a real number (int, float, numpy's scalars: float(value)); anything else is
/// a TypeError naming `what`.
std::optional<float> float_argument(const py::handle& value, const char* what);

/// nthreads as the CLI's -j takes it: 0 (one per core) or a thread count up to 2^32 - 1.
unsigned thread_count(const py::handle& nthreads);

/// `count` elements of `size` bytes, saturating at UINT64_MAX instead of wrapping.
uint64_t bytes_of(uint64_t count, uint64_t size);

/// Throws MemoryError "<what> needs <bytes> of memory, but only <available> is available" when
/// `bytes` exceeds what this process may still allocate (the CLI's check_memory: MemAvailable,
/// capped by RLIMIT_AS). Call it before allocating what a caller's sizes ask for.
void check_allocation(uint64_t bytes, const std::string& what);

/// `a` as a C-contiguous array of `dtype`: `a` itself when it already is one, otherwise a copy
/// made by numpy.ascontiguousarray after check_allocation (so that a broadcast array of 10^9 rows
/// is a MemoryError naming `what` and its shape, and numpy's own MemoryError reaches the caller
/// with its message).
py::array contiguous(const py::array& a, const py::dtype& dtype, const char* what);

/// The regular file at `path` as an InputFile in `role`, or nothing for a built-in name or a
/// special file.
std::optional<InputFile> input_file(const std::string& path, const char* role);

/// Refuses, before anything is written, an output `path` that is one of `inputs` (the same file
/// by identity, under any name: ValueError saying that writing it would destroy the input) or
/// an existing regular file when `overwrite` is false (FileExistsError saying to pass
/// overwrite=True). The CLI's prepare_output with --force as `overwrite`.
void refuse_clobber(const std::string& path, const std::vector<InputFile>& inputs, bool overwrite);

}  // namespace thicket::python
