#pragma once
/// float64 rays as their users hold them, for the precision=double structures: rows of doubles
/// (a .npy file of '<f8', a float64 numpy array) converted once into a batch, and the batch
/// answered by the same four queries as float rows (query/ray_rows.h), in double. Both front ends
/// (`thicket trace`, the Python module) read float64 rays through here and loop over none.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/query/crossings_double.h"
#include "thicket/query/ray_rows.h"
#include "thicket/core/ray_box.h"

namespace thicket {

/// float64 rows, RayRows' layouts.
using RayRowsD = RayRowsOf<double>;

/// A float64 batch's rays: valid[i] says whether row i has a meaning (make_ray()'s rules,
/// make_ray()'s), rays[i] is its ray when it has. The double structures take rays one at a time,
/// so the batch is converted whole, once.
struct RayBatchD {
    std::vector<RayD> rays;
    std::vector<uint8_t> valid;
    size_t size() const { return rays.size(); }
};

/// Converts every row of `rows` on `threads` threads (0: all cores); throws Error unless the
/// width is 6 or 8.
RayBatchD make_rays(const RayRowsD& rows, unsigned threads = 0);

/// The answers of ray_rows.h's four queries for a float64 batch, one per row in row order, a row
/// without a ray answering a miss (HitD{}, not occluded, no crossing). The structure must be
/// double_precision(): any other is refused before anything is traced, with
/// float64_rays_refusal()'s message; options.coherent is refused (no packet path in double).
/// Each returns the number of rows without a ray, except crossing_lists.
size_t closest_hits(const Accel& accel, const RayBatchD& batch, std::span<HitD> out, const BatchOptions& options = {});
size_t occlusions(const Accel& accel, const RayBatchD& batch, std::span<uint8_t> out,
                  const BatchOptions& options = {});
size_t crossing_counts(const Accel& accel, const RayBatchD& batch, std::span<uint32_t> out,
                       const BatchOptions& options = {});
/// Every crossing of every row, given `counts` from crossing_counts() over the same batch (the
/// caller learns the lists' size there and checks it against memory before they are made): row
/// i's crossings are hits[splits[i] .. splits[i+1]). Each ray is traced again, the same calls.
HitListsD crossing_lists(const Accel& accel, const RayBatchD& batch, std::span<const uint32_t> counts,
                         const BatchOptions& options = {});

}  // namespace thicket
