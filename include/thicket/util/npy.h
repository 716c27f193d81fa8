#pragma once
/// NumPy .npy files (format versions 1.0, 2.0 and 3.0), the exchange format of `thicket trace`:
/// rays come in as float32 (N, 8) arrays, hits go out as a structured array or a uint8 mask.
/// Every error is a thicket::Error whose message starts with the file's path.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "thicket/core/ray.h"

namespace thicket {

/// What a .npy header says. `descr` is the dtype as written: a string such as "<f4", or for a
/// structured dtype the fields' (name, type) pairs in `fields` (then `descr` is empty).
struct NpyHeader {
    int major = 1, minor = 0;
    std::string descr;
    std::vector<std::pair<std::string, std::string>> fields;
    bool fortran_order = false;
    std::vector<size_t> shape;
    size_t data_offset = 0;  ///< byte offset of the array data in the file

    size_t element_count() const;
};

/// A float array in C order.
struct NpyFloatArray {
    std::vector<size_t> shape;
    std::vector<float> values;
};

/// An opened .npy file: the header is read and checked once (magic, version, dict keys, shape,
/// C order) and the stream stays at the data. Each read_* checks the dtype and shape it needs and
/// that the data exactly fills the rest of the file, then reads it: one read per file.
class NpyFile {
public:
    explicit NpyFile(std::string path);

    const NpyHeader& header() const { return header_; }
    const std::string& path() const { return path_; }
    /// True for dtype '<f8': the caller picks read_matrix_double() to keep the precision.
    bool holds_float64() const { return header_.descr == "<f8"; }

    /// An array of dtype '<f4' or '<f8' (converted to float) of any shape.
    NpyFloatArray read_float();
    /// Same, and requires the shape (N, cols).
    NpyFloatArray read_matrix(size_t cols);
    /// Shape (N, cols), dtype '<f8' (or '<f4', widened exactly) as doubles in C order: the rays of
    /// `thicket trace` for a precision=double structure.
    std::vector<double> read_matrix_double(size_t cols);
    /// A 1-D array of dtype '|u1' or '|b1'.
    std::vector<uint8_t> read_u8();
    /// A 1-D array of the hits dtype written by write_npy_hits(); t, u, v, prim as stored.
    std::vector<Hit> read_hits();

private:
    /// Checks that `item_size` bytes per element fill the rest of the file, within memory.
    void check_data_size(size_t item_size);
    void read_bytes(void* dst, size_t n);
    void require_matrix(size_t cols) const;

    std::string path_;
    std::ifstream in_;
    NpyHeader header_;
};

/// The one-call forms, for a file read once: NpyFile(path).read_*().
NpyHeader read_npy_header(const std::string& path);
NpyFloatArray read_npy_float(const std::string& path);
NpyFloatArray read_npy_matrix(const std::string& path, size_t cols);
std::vector<double> read_npy_matrix_double(const std::string& path, size_t cols);
std::vector<uint8_t> read_npy_u8(const std::string& path);
std::vector<Hit> read_npy_hits(const std::string& path);

/// The structured dtype of hit records, as NumPy spells it.
inline constexpr const char* kNpyHitsDescr = "[('t', '<f4'), ('prim', '<u4'), ('u', '<f4'), ('v', '<f4')]";

/// Writes a float32 array; values.size() must equal the product of `shape`.
void write_npy_f32(const std::string& path, const std::vector<size_t>& shape, std::span<const float> values);
/// Writes a uint8 array of shape (N,).
void write_npy_u8(const std::string& path, std::span<const uint8_t> values);
/// Writes a uint32 array of shape (N,).
void write_npy_u32(const std::string& path, std::span<const uint32_t> values);
/// Writes a structured array of shape (N,) whose record is `fields` (name, type such as "<f4"),
/// packed without padding: `records` holds N records of the fields' summed size.
void write_npy_records(const std::string& path, const std::vector<std::pair<std::string, std::string>>& fields,
                       size_t count, std::span<const unsigned char> records);
/// Writes hits as the structured dtype kNpyHitsDescr, shape (N,): 16 bytes per record.
void write_npy_hits(const std::string& path, std::span<const Hit> hits);
/// Every writer goes through a temporary file and a rename (no partial file on failure), uses
/// format 1.0 (2.0 for headers over 64 KiB) and pads the header with spaces and a final newline so
/// that the data starts at a multiple of 64 bytes, as NumPy does.

}  // namespace thicket
