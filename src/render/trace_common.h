#pragma once
// Pieces the integrators and the views share (private to src/render): the fixed tiling, ray offsets, and the
// per-pixel sums that make an image independent of thread scheduling.
#include <algorithm>
#include <cmath>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/render/integrator.h"
#include "thicket/render/lights.h"
#include "thicket/render/sampling.h"

namespace thicket {

/// Tiles are kTraceTile x kTraceTile pixels whatever the thread count.
inline constexpr int kTraceTile = 16;
/// Paths per wave of the path tracer: a tile's samples go in waves of about this many paths.
inline constexpr uint32_t kTraceWave = 4096;

/// The fixed tiling of a width x height image that every renderer's parallel loop runs over:
/// kTraceTile x kTraceTile tiles, row-major.
struct Tiling {
    int width = 0, height = 0;
    int tiles_x() const { return (width + kTraceTile - 1) / kTraceTile; }
    size_t count() const { return size_t(tiles_x()) * size_t((height + kTraceTile - 1) / kTraceTile); }
    /// The image indices of tile `tile`, in 4x4 blocks so that each 16 consecutive camera rays
    /// are neighbours (bvh8's packets).
    void pixels(size_t tile, std::vector<uint32_t>& out) const {
        constexpr int kBlock = 4;
        out.clear();
        const int x0 = int(tile % size_t(tiles_x())) * kTraceTile, y0 = int(tile / size_t(tiles_x())) * kTraceTile;
        for (int by = y0; by < std::min(height, y0 + kTraceTile); by += kBlock)
            for (int bx = x0; bx < std::min(width, x0 + kTraceTile); bx += kBlock)
                for (int y = by; y < std::min(height, by + kBlock); ++y)
                    for (int x = bx; x < std::min(width, bx + kBlock); ++x) out.push_back(uint32_t(y * width + x));
    }
};

/// The camera rays through the centres of tile `tile`'s pixels, in Tiling::pixels' order
/// (`pixel` gets their image indices).
inline void tile_camera_rays(const Camera& camera, const Tiling& tiling, size_t tile, std::vector<uint32_t>& pixel,
                             std::vector<Ray>& rays) {
    tiling.pixels(tile, pixel);
    rays.clear();
    const uint32_t w = uint32_t(tiling.width);
    for (uint32_t p : pixel)
        rays.push_back(camera.generate(float(p % w) + 0.5f, float(p / w) + 0.5f, tiling.width, tiling.height));
}

/// The closest hits of one tile's rays into `found`, on this thread (the tiles are the parallel
/// loop): one coherent batch, or with `count` each ray alone, since the batch API's packets share
/// their node visits, and counted(k, counters) called for ray k.
template <class Counted>
void trace_tile(const Accel& accel, const std::vector<Ray>& rays, std::vector<Hit>& found, bool count,
                Counted&& counted) {
    found.resize(rays.size());
    if (count) {
        for (size_t k = 0; k < rays.size(); ++k) {
            RayCounters counters;
            found[k] = accel.intersect(rays[k], counters);
            counted(k, counters);
        }
        return;
    }
    BatchOptions batch;
    batch.threads = 1;
    batch.coherent = true;
    accel.intersect(rays, found, batch);
}

/// Offset that keeps a ray leaving point p off the surface it leaves: relative to p's magnitude.
inline float ray_epsilon(Vec3 p) { return 2e-4f * std::max(1.0f, max_component(abs(p))); }

/// A ray leaving surface point p (geometric normal n, either orientation) in direction dir.
inline Ray spawn_ray(Vec3 p, Vec3 n, Vec3 dir) {
    const Vec3 side = dot(dir, n) >= 0.0f ? n : -n;
    Ray r;
    r.org = p + side * ray_epsilon(p);
    r.dir = dir;
    r.tmin = 0.0f;
    r.tmax = kInfinity;
    return r;
}

/// A shadow ray from p toward a light point `distance` away along unit `dir`, stopping short of it.
/// It is aimed from its offset origin at the light point itself: kept parallel to `dir`, the offset
/// ray met a sphere light before its stopping distance near the sphere's rim, and 1.6-4% of a
/// sphere light's samples were shadowed by the light itself (LightTransport's closed-form test).
inline Ray shadow_ray(Vec3 p, Vec3 n, Vec3 dir, float distance) {
    Ray r = spawn_ray(p, n, dir);
    if (!std::isfinite(distance)) return r;  // a light at infinity: nothing to aim at
    const Vec3 to_light = p + dir * distance - r.org;
    const float length_to_light = length(to_light);
    if (!(length_to_light > 0.0f)) {
        r.tmax = 0.0f;
        return r;
    }
    r.dir = to_light / length_to_light;
    r.tmax = std::max(0.0f, length_to_light * (1.0f - 1e-4f) - 2.0f * ray_epsilon(p));
    return r;
}

/// Validates the options and sets up an empty result.
inline TraceResult begin_trace(const RenderScene& rs, const TraceOptions& o) {
    if (!rs.scene) throw Error("render: no scene");
    if (rs.prim_material.size() != rs.scene->primitive_count())
        throw Error("render: the scene has " + std::to_string(rs.scene->primitive_count()) + " primitives but " +
                    std::to_string(rs.prim_material.size()) + " material assignments");
    for (uint32_t id : rs.prim_material)
        if (id >= rs.materials.size()) throw Error("render: material index " + std::to_string(id) + " out of range");
    check_emitters(rs);  // every integrator: an emitter beyond the bound is refused, not rendered black
    constexpr int kMaxSide = 32768;
    if (o.width < 1 || o.height < 1 || o.width > kMaxSide || o.height > kMaxSide)
        throw Error("render: image size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                    " is not within 1x1 to 32768x32768");
    if (o.spp < 1) throw Error("render: --spp must be at least 1");
    if (o.max_depth < 1) throw Error("render: the maximum path depth must be at least 1");
    TraceResult r;
    r.width = o.width;
    r.height = o.height;
    r.spp = o.spp;
    const size_t pixels = size_t(o.width) * size_t(o.height);
    r.sum.assign(3 * pixels, 0.0);
    if (o.variance) r.lum_sum2.assign(pixels, 0.0);
    return r;
}

/// Adds one sample's radiance to pixel `pix` (NaN and infinite samples count as black).
inline void add_sample(TraceResult& r, uint32_t pix, Vec3 L, bool variance) {
    if (!(std::isfinite(L.x) && std::isfinite(L.y) && std::isfinite(L.z))) L = Vec3{};
    r.sum[3 * size_t(pix)] += L.x;
    r.sum[3 * size_t(pix) + 1] += L.y;
    r.sum[3 * size_t(pix) + 2] += L.z;
    if (variance) {
        const double l = luminance(L);
        r.lum_sum2[pix] += l * l;
    }
}

/// Means and variances from the sums.
inline void finish_trace(TraceResult& r) {
    const size_t pixels = size_t(r.width) * size_t(r.height);
    r.radiance.resize(pixels);
    const double n = r.spp;
    for (size_t i = 0; i < pixels; ++i)
        r.radiance[i] = Vec3{float(r.sum[3 * i] / n), float(r.sum[3 * i + 1] / n), float(r.sum[3 * i + 2] / n)};
    if (r.lum_sum2.empty()) return;
    r.lum_variance.assign(pixels, 0.0f);
    if (r.spp < 2) return;
    for (size_t i = 0; i < pixels; ++i) {
        const double mean = 0.2126 * r.sum[3 * i] / n + 0.7152 * r.sum[3 * i + 1] / n + 0.0722 * r.sum[3 * i + 2] / n;
        r.lum_variance[i] = float(std::max(0.0, (r.lum_sum2[i] - n * mean * mean) / (n - 1.0)));
    }
}

}  // namespace thicket
