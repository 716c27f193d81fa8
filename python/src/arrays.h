#pragma once
// numpy arrays in and out of the module: shape and dtype checks that name what was received, the
// conversion of ray rows to thicket::Ray, and output arrays that keep the input's leading shape.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/core/ray.h"
#include "thicket/util/parallel.h"
#include "thicket/util/prefetch.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace thicket::python {

namespace py = pybind11;

/// A C-contiguous float32 array of rows: `lead` is its shape without the last axis, `width` the
/// last axis, `count` the number of rows (the product of `lead`). Holding `array` keeps `data` valid.
struct Rows {
    py::array array;
    std::vector<py::ssize_t> lead;
    size_t width = 0;
    size_t count = 0;
    const float* data() const { return static_cast<const float*>(array.data()); }
};

/// "(3, 7)": a shape as Python prints it.
std::string shape_text(const py::array& a);

/// `obj` as rows of float32 whose last axis is one of `widths`; anything else is a ValueError
/// naming `what`, the shape and dtype received and what is expected. Never converts dtypes
/// silently (a float64 array is refused, as Open3D does): the caller says .astype(np.float32).
/// Copies only when the array is not C-contiguous.
Rows float32_rows(const py::handle& obj, const char* what, std::initializer_list<size_t> widths);

/// Rays made from rows of 6 (ox oy oz dx dy dz, interval [tnear, tfar]) or 8 floats (the interval in
/// the row). Rows without meaning (make_ray() refuses them) are left out and answered as misses:
/// then `compacted` is set and `rows` lists the row of each ray.
struct RayBatch {
    std::vector<Ray> rays;
    std::vector<size_t> rows;
    bool compacted = false;
    size_t row_of(size_t k) const { return compacted ? rows[k] : k; }
};

/// Converts `rows` on `threads` threads; call without the GIL.
RayBatch make_rays(const Rows& rows, float tnear, float tfar, unsigned threads);

/// Room for a chunk's kBatchGrain answers on the stack, left uninitialised: the batch call writes
/// every answer it is asked for, and the default member initialisers of Hit or NearestPoint would
/// cost a pass over the chunk before it.
template <class T>
struct Uninitialized {
    union {
        T data[kBatchGrain];
    };
    Uninitialized() {}
};

/// Rows [begin, end) of a batch as rays, converted by the thread that traces them and kept on its
/// stack: the rays never make a round trip through memory, and no array of rays or answers as
/// large as the batch is allocated and first touched. Rows without meaning are left out: ray k
/// is row begin + k of a complete chunk, else row begin + offset[k].
struct RayChunk {
    alignas(64) Uninitialized<Ray> rays;  // no ray across two cache lines
    uint16_t offset[kBatchGrain];
    size_t count = 0;
    size_t begin = 0;
    size_t end = 0;
    /// Whether every row became a ray (else the caller answers the others as misses first).
    bool complete() const { return count == end - begin; }
    /// The row of ray k.
    size_t row(size_t k) const { return begin + (complete() ? k : offset[k]); }
};

/// Converts rows [begin, end) (at most kBatchGrain) of `rows` into `chunk`.
void fill_chunk(const Rows& rows, float tnear, float tfar, size_t begin, size_t end, RayChunk& chunk);

/// Calls f(const RayChunk&) for the rows in chunks of kBatchGrain, the library's batch chunking,
/// on `threads` threads (0: all cores): each chunk is converted, traced and written out by one
/// thread. Each thread claims its next chunk before it traces the current one and asks for the
/// next one's rows first, so that they arrive while it traces: a batch's rows are cold, and the
/// conversion would otherwise wait for them. Call without the GIL.
template <class F>
void for_each_ray_chunk(const Rows& rows, float tnear, float tfar, unsigned threads, F&& f) {
    const size_t chunks = (rows.count + kBatchGrain - 1) / kBatchGrain;
    const size_t workers = std::min<size_t>(resolve_threads(threads), chunks);
    std::atomic<size_t> next{0};
    auto range = [&](size_t chunk) { return std::pair{chunk * kBatchGrain, std::min(rows.count, (chunk + 1) * kBatchGrain)}; };
    parallel_for(workers, 1, unsigned(workers), [&](size_t, size_t) {
        RayChunk chunk;
        size_t mine = next.fetch_add(1, std::memory_order_relaxed);
        try {
            while (mine < chunks) {
                const size_t ahead = next.fetch_add(1, std::memory_order_relaxed);
                const auto [begin, end] = range(mine);
                fill_chunk(rows, tnear, tfar, begin, end, chunk);
                if (ahead < chunks) {
                    const auto [first, last] = range(ahead);
                    prefetch_range(rows.data() + rows.width * first, (last - first) * rows.width * sizeof(float));
                }
                f(static_cast<const RayChunk&>(chunk));
                mine = ahead;
            }
        } catch (...) {
            next.store(chunks, std::memory_order_relaxed);  // the other threads start no further chunk
            throw;
        }
    });
}

/// What one chunk asks of the library's batch calls: one thread (the chunk's own), so that the
/// chunk is traced in place by the thread that converted it.
inline BatchOptions chunk_options(bool coherent) {
    BatchOptions o;
    o.threads = 1;
    o.coherent = coherent;
    return o;
}

/// Output arrays of at least this many bytes are written with non-temporal stores, which go to
/// memory without reading the line first: a plain store to a cold line reads it in, so that
/// cast_rays' 32 bytes of answers per ray moved 64, and the lines brought in evicted the nodes
/// that the tracing needs. A smaller array, which the caller reads at once, goes through the cache.
inline constexpr size_t kStreamBytes = size_t(1) << 20;

/// Non-temporal stores are weakly ordered: fenced, a thread's streamed answers are seen before
/// its later stores (the end of the parallel loop that hands the arrays back to Python among them).
inline void stream_fence() {
#if defined(__SSE2__)
    _mm_sfence();
#endif
}

/// tnear/tfar of the 6-column form; with 8 columns the row holds the interval and giving them too
/// is a ValueError (which one would win is not obvious).
void check_interval_arguments(const Rows& rows, std::optional<float> tnear, std::optional<float> tfar);

/// Memory for an output array of `bytes`, or an empty handle for numpy's own allocator: a large
/// array gets a mapping of its own, aligned to and advised for 2 MiB pages, which the capsule
/// returned releases when the array dies (kept for the next array of the same size, up to 256
/// MiB in all, else unmapped). Writing a batch's answers into fresh memory faults every page in;
/// on 4 KiB pages (numpy's malloc leaves most of a 4 MiB array on them) those faults cost more
/// than converting the rows (1M rays: 40 MB, 10^4 faults, ~100 ms on the virtualized machine
/// measured), on 2 MiB pages one fault in 512. `data` receives the memory; its contents are
/// undefined (every query writes every element).
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
