#include "arrays.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

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

namespace {

constexpr size_t kHugePage = size_t(2) << 20;
/// Smaller arrays stay with numpy: a mapping is rounded up to whole 2 MiB pages, so below 1 MiB
/// the memory given away would exceed the array. (A 10^6-ray boolean answer, 1 MB, is above.)
constexpr size_t kHugeArrayBytes = size_t(1) << 20;

/// A mapping that an output array views.
struct Mapping {
    void* start;
    size_t length;
};

/// Mappings whose arrays have died, kept for the next arrays of the same length: a loop over
/// batches asks for the same sizes every call, and a kept mapping's pages are already faulted in
/// and zeroed (the kernel zeroes a fresh 2 MiB page at ~5-10 GB/s: 40 MB of cast_rays answers cost
/// a few percent of tracing them). At most kKeptBytes are kept, the rest unmapped. Only touched
/// with the GIL held: arrays are made, and their capsules die, with it held.
std::vector<Mapping>& kept_mappings() {
    static std::vector<Mapping> kept;
    return kept;
}
size_t kept_bytes = 0;
constexpr size_t kKeptBytes = size_t(256) << 20;

#if defined(__linux__) && defined(MADV_HUGEPAGE)
/// A fresh mapping of `length` bytes (a multiple of kHugePage), 2 MiB-aligned and advised for
/// huge pages; null if the system refuses it.
void* map_huge(size_t length) {
    // One page more than needed, so that a 2 MiB-aligned start lies inside; the rest is returned.
    const size_t span = length + kHugePage;
    void* raw = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) return nullptr;
    const uintptr_t start = (reinterpret_cast<uintptr_t>(raw) + kHugePage - 1) / kHugePage * kHugePage;
    const size_t head = start - reinterpret_cast<uintptr_t>(raw);
    if (head) munmap(raw, head);
    if (span - head - length) munmap(reinterpret_cast<char*>(start) + length, span - head - length);
    madvise(reinterpret_cast<void*>(start), length, MADV_HUGEPAGE);  // a hint: ignored without THP
    return reinterpret_cast<void*>(start);
}
#endif

}  // namespace

py::capsule huge_page_memory(size_t bytes, void*& data) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (bytes < kHugeArrayBytes) return {};
    const size_t length = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    std::vector<Mapping>& kept = kept_mappings();
    data = nullptr;
    for (size_t i = 0; i < kept.size(); ++i)
        if (kept[i].length == length) {
            data = kept[i].start;
            kept_bytes -= length;
            kept.erase(kept.begin() + std::ptrdiff_t(i));
            break;
        }
    if (!data) data = map_huge(length);
    if (!data) return {};  // numpy's allocator will say why, if it fails too
    return py::capsule(new Mapping{data, length}, [](void* p) {
        const Mapping* m = static_cast<Mapping*>(p);
        if (kept_bytes + m->length <= kKeptBytes) {
            kept_mappings().push_back(*m);
            kept_bytes += m->length;
        } else {
            munmap(m->start, m->length);
        }
        delete m;
    });
#else
    (void)bytes;
    (void)data;
    return {};
#endif
}

namespace {

/// fill_chunk for rows of `Width` floats: make_ray's checks, written without branches (every row
/// is stored, and counted only if it has a meaning), which halves the cost of a row (~7 ns of the
/// ~11 ns the module added per ray on a single thread, measured with perf).
template <size_t Width>
void fill_rows(const float* data, float tnear, float tfar, size_t begin, size_t end, RayChunk& chunk) {
    constexpr float kMax = std::numeric_limits<float>::max();
    size_t count = 0;
    for (size_t i = begin; i < end; ++i) {
        const float* r = data + Width * i;
        float tmin = tnear, tmax = tfar;
        if constexpr (Width == 8) tmin = r[6], tmax = r[7];
        Ray& ray = chunk.rays[count];
        ray.org = {r[0], r[1], r[2]};
        ray.dir = {r[3], r[4], r[5]};
        ray.tmin = tmin;
        ray.tmax = tmax;
        // make_ray: a finite origin and direction, a non-zero direction, tmin <= tmax (no NaN).
        bool ok = true;
        for (int k = 0; k < 6; ++k) ok &= std::fabs(r[k]) <= kMax;
        ok &= (r[3] != 0.0f) | (r[4] != 0.0f) | (r[5] != 0.0f);
        ok &= tmin <= tmax;
        chunk.offset[count] = uint16_t(i - begin);
        count += ok;
    }
    chunk.count = count;
}

}  // namespace

void fill_chunk(const Rows& rows, float tnear, float tfar, size_t begin, size_t end, RayChunk& chunk) {
    static_assert(kBatchGrain <= 65536, "RayChunk::offset is 16 bits");
    chunk.begin = begin;
    chunk.end = end;
    if (rows.width == 8)
        fill_rows<8>(rows.data(), tnear, tfar, begin, end, chunk);
    else
        fill_rows<6>(rows.data(), tnear, tfar, begin, end, chunk);
}

}  // namespace thicket::python
