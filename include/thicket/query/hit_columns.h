#pragma once
/// Closest hits written out as columns, the layout Open3D's cast_rays returns and the Python
/// module fills: t, geometry id, primitive id, (u, v) and normal, one row per ray. The columns are
/// written by the threads that trace the chunks, with non-temporal stores when they are large, so
/// that answering does not evict the nodes the tracing needs.
#include <cstddef>
#include <cstdint>

#include "thicket/query/ray_rows.h"
#include "thicket/core/ray.h"
#include "thicket/core/vec3.h"

namespace thicket {

struct Scene;

/// Columns of at least this many bytes are written with non-temporal stores, which go to memory
/// without reading the line first: a plain store to a cold line reads it in, so that cast_rays'
/// 32 bytes of answers per ray moved 64, and the lines brought in evicted the nodes that the
/// tracing needs. A smaller column, which the caller reads at once, goes through the cache.
inline constexpr size_t kStreamBytes = size_t(1) << 20;

/// The five columns of closest hits. A miss is t +inf (not the ray's tmax: Open3D's and `thicket
/// trace`'s convention), ids 4294967295, zero (u, v) and normal.
struct HitColumns {
    float* t = nullptr;
    uint32_t* geom = nullptr;
    uint32_t* prim = nullptr;
    float* uv = nullptr;   ///< two per row
    float* nrm = nullptr;  ///< three per row
    const Scene* scene = nullptr;  ///< names each hit's geometry (Scene::geometry_of) and normal
    /// Non-temporal stores: set by stream_when_large().
    bool stream = false;

    /// Streams when the columns of `rows` rows take kStreamBytes or more and every column is
    /// 16-byte aligned (what the four-row stores need).
    void stream_when_large(size_t rows);

    /// Row `row` answers `hit`, whose normal is `n`.
    void put(size_t row, const Hit& hit, const Vec3& n) const;

    /// Writes chunk `c`'s answers, hits[k] being ray k's, the rows without a ray as misses. Normals
    /// come from `normals` when given (one per triangle, then a zero entry for a miss at
    /// `miss_entry` and one more to read any entry as four floats), else from Scene::normal at the
    /// hit. Streamed stores are fenced before it returns, so that the chunk is seen by whoever
    /// joins the thread.
    void put_chunk(const RayChunk& c, const Hit* hits, const Vec3* normals, uint32_t miss_entry) const;
};

}  // namespace thicket
