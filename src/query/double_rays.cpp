// The float64 batch of the front ends (query/double_rays.h): rows converted once, answered in
// double ray by ray (the precision=double structures take no chunks).
#include "thicket/query/double_rays.h"

#include <algorithm>
#include <string>

#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket {

namespace {

/// What every query of a float64 batch checks before it traces.
void check_double_batch(const Accel& accel, const char* query, const RayBatchD& batch, size_t answers,
                        const BatchOptions& options) {
    check_ray_answers(query, batch.size(), answers);
    refuse_coherent(query, options);  // no packet path in double
    if (!accel.double_precision())
        throw Error(float64_rays_refusal("float64 batch", "structure '" + accel.spec() + "'", "trace float rays"));
}

/// Calls answer(i) for every row with a ray and miss(i) for the others, on options.threads
/// threads, telling options.progress of each chunk; returns the rows without a ray.
template <class Answer, class Miss>
size_t for_each_row(const RayBatchD& batch, const BatchOptions& options, Answer&& answer, Miss&& miss) {
    parallel_for(batch.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) batch.valid[i] ? answer(i) : miss(i);
        if (options.progress) options.progress(end - begin);
    });
    return size_t(std::count(batch.valid.begin(), batch.valid.end(), uint8_t(0)));
}

}  // namespace

RayBatchD make_rays(const RayRowsD& rows, unsigned threads) {
    if (rows.width != 6 && rows.width != 8)
        throw Error("float64 rays: rows of " + std::to_string(rows.width) + " values; expected 8 (ox oy oz dx dy dz "
                    "tmin tmax) or 6 (ox oy oz dx dy dz)");
    RayBatchD batch;
    batch.rays.resize(rows.count);
    batch.valid.resize(rows.count);
    parallel_for(rows.count, kBatchGrain, threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const double* row = rows.data + i * rows.width;
            double r[8];
            std::copy(row, row + 6, r);
            r[6] = rows.width == 8 ? row[6] : rows.tmin;
            r[7] = rows.width == 8 ? row[7] : rows.tmax;
            batch.valid[i] = make_ray(r, batch.rays[i]) ? 1 : 0;
        }
    });
    return batch;
}

size_t closest_hits(const Accel& accel, const RayBatchD& batch, std::span<HitD> out, const BatchOptions& options) {
    check_double_batch(accel, "float64 closest-hit", batch, out.size(), options);
    return for_each_row(
        batch, options, [&](size_t i) { out[i] = accel.intersect_double(batch.rays[i]); },
        [&](size_t i) { out[i] = HitD{}; });
}

size_t occlusions(const Accel& accel, const RayBatchD& batch, std::span<uint8_t> out, const BatchOptions& options) {
    check_double_batch(accel, "float64 any-hit", batch, out.size(), options);
    return for_each_row(
        batch, options, [&](size_t i) { out[i] = accel.occluded_double(batch.rays[i]) ? 1 : 0; },
        [&](size_t i) { out[i] = 0; });
}

size_t crossing_counts(const Accel& accel, const RayBatchD& batch, std::span<uint32_t> out,
                       const BatchOptions& options) {
    check_double_batch(accel, "float64 count", batch, out.size(), options);
    return for_each_row(
        batch, options, [&](size_t i) { out[i] = count_hits_double(accel, batch.rays[i]); },
        [&](size_t i) { out[i] = 0; });
}

HitListsD crossing_lists(const Accel& accel, const RayBatchD& batch, std::span<const uint32_t> counts,
                         const BatchOptions& options) {
    check_double_batch(accel, "float64 crossing lists", batch, counts.size(), options);
    HitListsD lists;
    lists.splits.assign(batch.size() + 1, 0);
    for (size_t i = 0; i < batch.size(); ++i) lists.splits[i + 1] = lists.splits[i] + counts[i];
    lists.hits.resize(lists.splits.back());
    parallel_for(batch.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        std::vector<HitD> mine;
        for (size_t i = begin; i < end; ++i) {
            if (!batch.valid[i]) continue;
            mine.clear();
            all_hits_double(accel, batch.rays[i], mine);
            std::copy_n(mine.begin(), std::min<size_t>(mine.size(), counts[i]), lists.hits.begin() + lists.splits[i]);
        }
        if (options.progress) options.progress(end - begin);
    });
    return lists;
}

}  // namespace thicket
