#pragma once
/// Rays as their users hold them: rows of floats (a .npy file, a numpy array, a buffer), turned
/// into rays chunk by chunk and answered in place. Every front end (the `thicket` tool, the Python
/// module) reads rows through here, so a row means the same ray everywhere: make_ray() (core/ray.h)
/// says which rows have a meaning, and a row without one is answered as a miss.
#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/accel/ray_order.h"
#include "thicket/core/ray.h"
#include "thicket/util/parallel.h"
#include "thicket/util/prefetch.h"

namespace thicket {

/// `count` rows of `width` values at `data`: width 8 is ox oy oz dx dy dz tmin tmax; width 6 is
/// ox oy oz dx dy dz, every row with the interval [tmin, tmax] given here. float rows are RayRows;
/// double rows (RayRowsD, query/double_rays.h) are float64 rays for the precision=double structures.
template <class Scalar>
struct RayRowsOf {
    const Scalar* data = nullptr;
    size_t count = 0;
    size_t width = 8;
    Scalar tmin = 0;
    Scalar tmax = std::numeric_limits<Scalar>::infinity();
};
using RayRows = RayRowsOf<float>;

/// Throws Error unless `rows` has width 6 or 8 (the only layouts fill_chunk reads).
void check_ray_rows(const RayRows& rows);

/// Room for `N` values of T on the stack, left uninitialised: a batch call writes every answer it
/// is asked for, and the default member initialisers of Hit, Ray or NearestPoint would cost a pass
/// over the chunk before it.
template <class T, size_t N = kBatchGrain>
struct Uninitialized {
    union {
        T data[N];
    };
    Uninitialized() {}
};

/// Rows of a batch as rays, converted by the thread that traces them and kept on its stack: the
/// rays never make a round trip through memory, and no array of rays or answers as large as the
/// batch is allocated and first touched. The chunk holds positions [begin, end) of the batch in
/// the order it is traced: rows begin.. end - 1 as given, or in a reordered block
/// (accel/ray_order.h) the rows `sorted_base + sorted[j]`. Rows without a meaning are left out:
/// ray k is position k of a complete chunk, else position offset[k].
struct RayChunk {
    alignas(64) Uninitialized<Ray> rays;  // no ray across two cache lines
    uint16_t offset[kBatchGrain];
    size_t count = 0;
    size_t begin = 0;
    size_t end = 0;
    const uint32_t* sorted = nullptr;  ///< a reordered block's rows, from the chunk's first position
    size_t sorted_base = 0;            ///< the block's first row
    /// Whether every row became a ray (else the caller answers the others as misses).
    bool complete() const { return count == end - begin; }
    /// Whether ray k is row begin + k for every k.
    bool contiguous() const { return complete() && !sorted; }
    /// The row at position j of the chunk (0 <= j < end - begin), a ray or not.
    size_t row_at(size_t j) const { return sorted ? sorted_base + sorted[j] : begin + j; }
    /// The row of ray k.
    size_t row(size_t k) const { return row_at(complete() ? k : offset[k]); }
    /// Calls f(row) for each row of the chunk that has no ray.
    template <class F>
    void for_each_row_without_ray(F&& f) const {
        if (complete()) return;
        size_t k = 0;  // offset[] lists the positions with a ray, in increasing order
        for (size_t j = 0; j < end - begin; ++j) {
            if (k < count && offset[k] == j)
                ++k;
            else
                f(row_at(j));
        }
    }
    std::span<const Ray> span() const { return {rays.data, count}; }
};

/// Converts positions [begin, end) (at most kBatchGrain) of `rows` into `chunk`, with make_ray()'s
/// checks: rows begin.. end - 1, or with `sorted` the rows sorted_base + sorted[j], j < end - begin.
void fill_chunk(const RayRows& rows, size_t begin, size_t end, RayChunk& chunk, const uint32_t* sorted = nullptr,
                size_t sorted_base = 0);

/// Calls f(const RayChunk&) for the rows in chunks of kBatchGrain on `threads` threads (0: all
/// cores): each chunk is converted, answered and written out by one thread, which asks the
/// structure for that chunk alone (Accel::intersect_chunk and its kin): the batch is split once.
/// `reorder_from_ns` (reorder_from(options); infinity: as given): a batch of kReorderMin rows or
/// more is handed out in blocks; a thread traces a block's first two chunks as given and, when
/// the second cost at least reorder_from_ns a ray (costly_rays), sorts the rest (RayOrder) and
/// converts it chunk by chunk in that order. Each thread asks for the next chunk's rows before
/// it traces the current one (a batch's rows are cold, and the conversion would otherwise wait
/// for them; a sorted block's rows are read by its sort first).
/// An exception from f stops every thread's next chunk and reaches the caller.
template <class F>
void for_each_ray_chunk(const RayRows& rows, unsigned threads, double reorder_from_ns, F&& f) {
    if (!std::isinf(reorder_from_ns) && rows.count >= kReorderMin) {
        struct Scratch {
            RayOrder order;
            RayChunk chunk;
        };
        const size_t block = reorder_block(rows.count, resolve_threads(threads));
        parallel_for_with<Scratch>(rows.count, block, threads, [&](size_t begin, size_t end, Scratch& s) {
            auto as_given = [&](size_t first, size_t last) {
                for (size_t k = first; k < last; k += kBatchGrain) {
                    fill_chunk(rows, k, std::min(last, k + kBatchGrain), s.chunk);
                    const size_t ahead = std::min(end, k + kBatchGrain), beyond = std::min(end, ahead + kBatchGrain);
                    prefetch_range(rows.data + rows.width * ahead, (beyond - ahead) * rows.width * sizeof(float));
                    f(static_cast<const RayChunk&>(s.chunk));
                }
            };
            // The first two chunks as given, the second timed (the first may find the structure, or
            // this block's rows, out of the cache): cheap rays trace the rest of the block as given.
            const size_t probe = std::min(end, begin + kBatchGrain), from = std::min(end, probe + kBatchGrain);
            as_given(begin, probe);
            if (!costly_rays(from - probe, reorder_from_ns, [&] { as_given(probe, from); })) return as_given(from, end);
            s.order.sort(end - from, [&](size_t i, Vec3& org, Vec3& dir) {
                const float* r = rows.data + rows.width * (from + i);
                org = {r[0], r[1], r[2]};
                dir = {r[3], r[4], r[5]};
            });
            for (size_t k = from; k < end; k += kBatchGrain) {
                fill_chunk(rows, k, std::min(end, k + kBatchGrain), s.chunk, s.order.order.data() + (k - from), from);
                f(static_cast<const RayChunk&>(s.chunk));
            }
        });
        return;
    }
    const size_t chunks = (rows.count + kBatchGrain - 1) / kBatchGrain;
    const size_t workers = std::min<size_t>(resolve_threads(threads), chunks);
    std::atomic<size_t> next{0};
    auto range = [&](size_t chunk) {
        return std::pair{chunk * kBatchGrain, std::min(rows.count, (chunk + 1) * kBatchGrain)};
    };
    parallel_for(workers, 1, unsigned(workers), [&](size_t, size_t) {
        RayChunk chunk;
        size_t mine = next.fetch_add(1, std::memory_order_relaxed);
        try {
            while (mine < chunks) {
                const size_t ahead = next.fetch_add(1, std::memory_order_relaxed);
                const auto [begin, end] = range(mine);
                fill_chunk(rows, begin, end, chunk);
                if (ahead < chunks) {
                    const auto [first, last] = range(ahead);
                    prefetch_range(rows.data + rows.width * first, (last - first) * rows.width * sizeof(float));
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

/// The rays of a whole batch of rows, for the queries that need them all at once (all_hits'
/// lists): rows without a meaning are left out, and then `compacted` is set and `rows` lists the
/// row of each ray.
struct RayBatch {
    std::vector<Ray> rays;
    std::vector<size_t> rows;
    bool compacted = false;
    size_t row_of(size_t k) const { return compacted ? rows[k] : k; }
};

/// Converts every row on `threads` threads (0: all cores).
RayBatch make_rays(const RayRows& rows, unsigned threads);

/// What the front ends answer for each row (a row without a ray answers a miss: Hit{}, not
/// occluded, no crossing). `out` receives one answer per row, in row order; `options.progress`
/// hears of every chunk; each returns the number of rows without a ray. These are the one path from rows to answers that `thicket trace` and the
/// tests use; the Python module writes its numpy outputs from the same chunks (for_each_ray_chunk).
size_t closest_hits(const Accel& accel, const RayRows& rows, std::span<Hit> out, const BatchOptions& options = {});
size_t occlusions(const Accel& accel, const RayRows& rows, std::span<uint8_t> out, const BatchOptions& options = {});
size_t crossing_counts(const Accel& accel, const RayRows& rows, std::span<uint32_t> out,
                       const BatchOptions& options = {});
/// Every crossing of every row: the crossings of row i are hits[splits[i] .. splits[i+1]) (a row
/// without a ray has none).
HitLists crossing_lists(const Accel& accel, const RayRows& rows, const BatchOptions& options = {});

}  // namespace thicket
