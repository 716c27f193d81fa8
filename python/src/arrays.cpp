#include "arrays.h"

#include <algorithm>
#include <atomic>

#include "thicket/accel/accel.h"
#include "thicket/util/parallel.h"

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

Rows float32_rows(const py::handle& obj, const char* what, std::initializer_list<size_t> widths) {
    if (!py::isinstance<py::array>(obj))
        throw py::value_error(std::string(what) + ": expected a numpy float32 array of shape " + widths_text(widths) +
                              ", got " + std::string(py::str(py::type::of(obj).attr("__name__"))));
    py::array a = py::reinterpret_borrow<py::array>(obj);
    const std::string received = shape_text(a) + " " + std::string(py::str(a.dtype()));
    const bool width_ok = a.ndim() >= 1 && std::find(widths.begin(), widths.end(), size_t(a.shape(a.ndim() - 1))) != widths.end();
    if (!width_ok)
        throw py::value_error(std::string(what) + ": expected shape " + widths_text(widths) + ", got shape " + received);
    if (!a.dtype().is(py::dtype::of<float>()))
        throw py::value_error(std::string(what) + ": expected dtype float32, got shape " + received +
                              " (convert with .astype(numpy.float32))");
    Rows r;
    // Copies only a strided or byte-swapped array; a C-contiguous float32 array is used in place.
    r.array = py::array_t<float, py::array::c_style>::ensure(a);
    if (!r.array) throw py::error_already_set();
    r.width = size_t(a.shape(a.ndim() - 1));
    r.count = 1;
    for (py::ssize_t i = 0; i + 1 < a.ndim(); ++i) {
        r.lead.push_back(a.shape(i));
        r.count *= size_t(a.shape(i));
    }
    return r;
}

void check_interval_arguments(const Rows& rows, std::optional<float> tnear, std::optional<float> tfar) {
    if (rows.width == 8 && (tnear || tfar))
        throw py::value_error("rays of 8 columns carry tmin and tmax in columns 6 and 7; tnear/tfar apply only to "
                              "rays of 6 columns");
}

RayBatch make_rays(const Rows& rows, float tnear, float tfar, unsigned threads) {
    RayBatch batch;
    batch.rays.resize(rows.count);
    std::vector<uint8_t> valid(rows.count);
    std::atomic<size_t> invalid{0};
    const float* data = rows.data();
    const size_t width = rows.width;
    parallel_for(rows.count, 4 * kBatchGrain, threads, [&](size_t begin, size_t end) {
        size_t bad = 0;
        for (size_t i = begin; i < end; ++i) {
            const float* r = data + width * i;
            float row[8] = {r[0], r[1], r[2], r[3], r[4], r[5], tnear, tfar};
            if (width == 8) row[6] = r[6], row[7] = r[7];
            valid[i] = make_ray(row, batch.rays[i]) ? 1 : 0;
            bad += 1 - valid[i];
        }
        invalid += bad;
    });
    if (invalid == 0) return batch;
    // Rare: compact the rays that have a meaning and remember their rows.
    size_t k = 0;
    batch.rows.reserve(rows.count - invalid);
    for (size_t i = 0; i < rows.count; ++i)
        if (valid[i]) {
            batch.rays[k++] = batch.rays[i];
            batch.rows.push_back(i);
        }
    batch.rays.resize(k);
    batch.compacted = true;
    return batch;
}

void fill_chunk(const Rows& rows, float tnear, float tfar, size_t begin, size_t end, RayChunk& chunk) {
    static_assert(kBatchGrain <= 65536, "RayChunk::offset is 16 bits");
    chunk.begin = begin;
    chunk.end = end;
    chunk.count = 0;
    const float* data = rows.data();
    const size_t width = rows.width;
    for (size_t i = begin; i < end; ++i) {
        const float* r = data + width * i;
        float row[8] = {r[0], r[1], r[2], r[3], r[4], r[5], tnear, tfar};
        if (width == 8) row[6] = r[6], row[7] = r[7];
        if (!make_ray(row, chunk.rays[chunk.count])) continue;
        chunk.offset[chunk.count++] = uint16_t(i - begin);
    }
}

}  // namespace thicket::python
