// Rows of floats to rays and their answers: the conversion every front end shares.
#include "thicket/query/ray_rows.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "thicket/core/error.h"

namespace thicket {

void check_ray_rows(const RayRows& rows) {
    if (rows.width != 6 && rows.width != 8)
        throw Error("rays: rows of " + std::to_string(rows.width) + " floats; a ray is a row of 6 (ox oy oz dx dy dz) "
                    "or 8 (ox oy oz dx dy dz tmin tmax)");
}

namespace {

/// make_ray() on a ray already made.
bool has_meaning(const Ray& ray) {
    const float r[8] = {ray.org.x, ray.org.y, ray.org.z, ray.dir.x, ray.dir.y, ray.dir.z, ray.tmin, ray.tmax};
    Ray unused;
    return make_ray(r, unused);
}

#if defined(__SSE2__)
/// One row as a Ray, and whether it has a meaning, without a branch: make_ray()'s checks (a finite
/// origin and direction, a non-zero direction, tmin <= tmax and no NaN) on `a` = ox oy oz dx and
/// `b` = dy dz tmin tmax. Four shuffles put them in Ray's order. The unit test RayRows.* holds it
/// to make_ray() on every special value.
inline bool store_ray(__m128 a, __m128 b, Ray& ray) {
    static_assert(sizeof(Ray) == 8 * sizeof(float) && offsetof(Ray, tmin) == 12 && offsetof(Ray, dir) == 16 &&
                      offsetof(Ray, tmax) == 28,
                  "Ray is ox oy oz tmin dx dy dz tmax");
    const __m128 a2b2 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 2, 2, 2));   // oz oz tmin tmin
    const __m128 org = _mm_shuffle_ps(a, a2b2, _MM_SHUFFLE(2, 1, 1, 0));  // ox oy oz tmin
    const __m128 a3b0 = _mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 3, 3));   // dx dx dy dy
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

/// fill_chunk for rows of `Width` floats (Sorted: the chunk's rows are sorted_base + sorted[j]).
/// Position j becomes ray j, and whether it has a
/// meaning is only summed, so that no store waits for the previous row's checks (compacting as
/// it goes made each row's store address depend on them: a chain of ~10 cycles per row). Rows
/// without a meaning are rare; then a second pass compacts the chunk.
template <size_t Width, bool Sorted>
void fill_rows(const RayRows& rows, RayChunk& chunk) {
    size_t count = 0;
    const size_t n = chunk.end - chunk.begin;
    for (size_t j = 0; j < n; ++j) {
        const float* r = rows.data + Width * (Sorted ? chunk.sorted_base + chunk.sorted[j] : chunk.begin + j);
        Ray& ray = chunk.rays.data[j];
#if defined(__SSE2__)
        const __m128 a = _mm_loadu_ps(r);
        __m128 b;
        if constexpr (Width == 8)
            b = _mm_loadu_ps(r + 4);
        else  // dy dz from the row, the interval from the rows' own
            b = _mm_movelh_ps(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(r + 4))),
                              _mm_setr_ps(rows.tmin, rows.tmax, 0, 0));
        count += store_ray(a, b, ray);
#else
        float row[8] = {r[0], r[1], r[2], r[3], r[4], r[5], rows.tmin, rows.tmax};
        if constexpr (Width == 8) row[6] = r[6], row[7] = r[7];
        ray.org = {row[0], row[1], row[2]};
        ray.dir = {row[3], row[4], row[5]};
        ray.tmin = row[6];
        ray.tmax = row[7];
        count += has_meaning(ray);
#endif
    }
    chunk.count = count;
    if (count == n) return;
    size_t k = 0;
    for (size_t j = 0; j < n; ++j)
        if (has_meaning(chunk.rays.data[j])) {
            chunk.rays.data[k] = chunk.rays.data[j];
            chunk.offset[k++] = uint16_t(j);
        }
}

/// Answers every row in `out` (a row without a ray gets `miss`): trace(chunk, answers) answers a
/// chunk's rays on the calling thread. Returns the number of rows without a ray.
template <class Answer, class Trace>
size_t answer_rows(const RayRows& rows, std::span<Answer> out, const BatchOptions& options, Answer miss, Trace&& trace) {
    check_ray_rows(rows);
    if (out.size() != rows.count)
        throw Error("rays: " + std::to_string(rows.count) + " rows but room for " + std::to_string(out.size()) +
                    " answers");
    std::atomic<size_t> without_ray{0};
    for_each_ray_chunk(rows, options.threads, reorder_from(options), [&](const RayChunk& c) {
        Uninitialized<Answer> answers;
        trace(c, answers.data);
        if (!c.complete()) {
            c.for_each_row_without_ray([&](size_t row) { out[row] = miss; });
            without_ray += c.end - c.begin - c.count;
        }
        for (size_t k = 0; k < c.count; ++k) out[c.row(k)] = answers.data[k];
        if (options.progress) options.progress(c.end - c.begin);
    });
    return without_ray;
}

}  // namespace

void fill_chunk(const RayRows& rows, size_t begin, size_t end, RayChunk& chunk, const uint32_t* sorted,
                size_t sorted_base) {
    static_assert(kBatchGrain <= 65536, "RayChunk::offset is 16 bits");
    chunk.begin = begin;
    chunk.end = end;
    chunk.sorted = sorted;
    chunk.sorted_base = sorted_base;
    if (rows.width == 8)
        sorted ? fill_rows<8, true>(rows, chunk) : fill_rows<8, false>(rows, chunk);
    else
        sorted ? fill_rows<6, true>(rows, chunk) : fill_rows<6, false>(rows, chunk);
}

RayBatch make_rays(const RayRows& rows, unsigned threads) {
    check_ray_rows(rows);
    RayBatch batch;
    batch.rays.resize(rows.count);
    std::vector<uint8_t> valid(rows.count);
    std::atomic<size_t> invalid{0};
    parallel_for(rows.count, 4 * kBatchGrain, threads, [&](size_t begin, size_t end) {
        size_t bad = 0;
        for (size_t i = begin; i < end; ++i) {
            const float* r = rows.data + rows.width * i;
            float row[8] = {r[0], r[1], r[2], r[3], r[4], r[5], rows.tmin, rows.tmax};
            if (rows.width == 8) row[6] = r[6], row[7] = r[7];
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

size_t closest_hits(const Accel& accel, const RayRows& rows, std::span<Hit> out, const BatchOptions& options) {
    return answer_rows<Hit>(rows, out, options, Hit{}, [&](const RayChunk& c, Hit* hits) {
        accel.intersect_chunk(c.span(), {hits, c.count}, options.coherent);
        // A miss is +inf, not the ray's tmax (Open3D's and `thicket trace`'s convention).
        for (size_t k = 0; k < c.count; ++k)
            if (!hits[k].found()) hits[k] = Hit{};
    });
}

size_t occlusions(const Accel& accel, const RayRows& rows, std::span<uint8_t> out, const BatchOptions& options) {
    refuse_coherent("any-hit", options);
    return answer_rows<uint8_t>(rows, out, options, 0, [&](const RayChunk& c, uint8_t* occluded) {
        accel.occluded_chunk(c.span(), {occluded, c.count});
    });
}

size_t crossing_counts(const Accel& accel, const RayRows& rows, std::span<uint32_t> out, const BatchOptions& options) {
    refuse_coherent("count", options);
    return answer_rows<uint32_t>(rows, out, options, 0, [&](const RayChunk& c, uint32_t* counts) {
        for (size_t k = 0; k < c.count; ++k) counts[k] = accel.count_hits(c.rays.data[k]);
    });
}

HitLists crossing_lists(const Accel& accel, const RayRows& rows, const BatchOptions& options) {
    refuse_coherent("all-hits", options);
    const RayBatch batch = make_rays(rows, options.threads);
    HitLists lists = accel.all_hits(batch.rays, options);
    if (!batch.compacted) return lists;
    // Rows without a ray have no crossings: their split repeats the previous one.
    std::vector<size_t> splits(rows.count + 1, 0);
    for (size_t k = 0, row = 0; row < rows.count; ++row) {
        const bool has_ray = k < batch.rays.size() && batch.rows[k] == row;
        splits[row + 1] = has_ray ? lists.splits[k + 1] : splits[row];
        k += has_ray;
    }
    lists.splits = std::move(splits);
    return lists;
}

}  // namespace thicket
