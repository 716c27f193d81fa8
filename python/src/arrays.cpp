#include "arrays.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif
#if defined(__SSE2__)
#include <emmintrin.h>
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

#if defined(__SSE2__)
/// One row as a Ray, and whether it has a meaning (make_ray's checks: a finite origin and
/// direction, a non-zero direction, tmin <= tmax and no NaN), without a branch: `a` holds
/// ox oy oz dx, `b` dy dz tmin tmax. Four shuffles put them in Ray's order.
inline bool store_ray(__m128 a, __m128 b, Ray& ray) {
    static_assert(sizeof(Ray) == 8 * sizeof(float) && offsetof(Ray, tmin) == 12 && offsetof(Ray, dir) == 16 &&
                      offsetof(Ray, tmax) == 28,
                  "Ray is ox oy oz tmin dx dy dz tmax");
    const __m128 a2b2 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 2, 2, 2));  // oz oz tmin tmin
    const __m128 org = _mm_shuffle_ps(a, a2b2, _MM_SHUFFLE(2, 1, 1, 0));  // ox oy oz tmin
    const __m128 a3b0 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 3, 3));  // dx dx dy dy
    const __m128 dir = _mm_shuffle_ps(a3b0, b, _MM_SHUFFLE(3, 1, 2, 0));  // dx dy dz tmax
    _mm_storeu_ps(&ray.org.x, org);
    _mm_storeu_ps(&ray.dir.x, dir);
    // |x| <= FLT_MAX is false for an infinity and a NaN.
    const __m128 abs_mask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    const __m128 max = _mm_set1_ps(std::numeric_limits<float>::max());
    const int finite = _mm_movemask_ps(_mm_cmple_ps(_mm_and_ps(org, abs_mask), max)) &
                       _mm_movemask_ps(_mm_cmple_ps(_mm_and_ps(dir, abs_mask), max));
    const int nonzero = _mm_movemask_ps(_mm_cmpneq_ps(dir, _mm_setzero_ps()));
    // The origin's and direction's lanes 0-2 finite, one direction lane non-zero, tmin <= tmax.
    return ((finite & 7) == 7) & ((nonzero & 7) != 0) & (ray.tmin <= ray.tmax);
}
#endif

/// make_ray's checks on a ray already made: a finite origin and direction, a non-zero direction,
/// tmin <= tmax (no NaN).
bool has_meaning(const Ray& ray) {
    const float r[8] = {ray.org.x, ray.org.y, ray.org.z, ray.dir.x, ray.dir.y, ray.dir.z, ray.tmin, ray.tmax};
    Ray unused;
    return make_ray(r, unused);
}

/// fill_chunk for rows of `Width` floats. Row i becomes ray i - begin, and whether it has a
/// meaning is only summed, so that no store waits for the previous row's checks (compacting as
/// it goes made each row's store address depend on them: a chain of ~10 cycles per row). Rows
/// without a meaning are rare; then a second pass compacts the chunk.
template <size_t Width>
void fill_rows(const float* data, float tnear, float tfar, size_t begin, size_t end, RayChunk& chunk) {
    size_t count = 0;
    for (size_t i = begin; i < end; ++i) {
        const float* r = data + Width * i;
        Ray& ray = chunk.rays.data[i - begin];
#if defined(__SSE2__)
        const __m128 a = _mm_loadu_ps(r);
        __m128 b;
        if constexpr (Width == 8)
            b = _mm_loadu_ps(r + 4);
        else  // dy dz from the row, the interval from the arguments
            b = _mm_movelh_ps(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(r + 4))), _mm_setr_ps(tnear, tfar, 0, 0));
        count += store_ray(a, b, ray);
#else
        float row[8] = {r[0], r[1], r[2], r[3], r[4], r[5], tnear, tfar};
        if constexpr (Width == 8) row[6] = r[6], row[7] = r[7];
        ray.org = {row[0], row[1], row[2]};
        ray.dir = {row[3], row[4], row[5]};
        ray.tmin = row[6];
        ray.tmax = row[7];
        count += has_meaning(ray);
#endif
    }
    chunk.count = count;
    if (count == end - begin) return;
    size_t k = 0;
    for (size_t j = 0; j < end - begin; ++j)
        if (has_meaning(chunk.rays.data[j])) {
            chunk.rays.data[k] = chunk.rays.data[j];
            chunk.offset[k++] = uint16_t(j);
        }
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
