#include "thicket/render/view_buffers.h"

#include <algorithm>
#include <limits>
#include <string>

#include "thicket/core/error.h"
#include "thicket/render/image.h"
#include "thicket/util/input_file.h"
#include "thicket/util/parallel.h"
#include "trace_common.h"

namespace thicket {

namespace {

uint32_t saturate32(uint64_t n) { return uint32_t(std::min<uint64_t>(n, std::numeric_limits<uint32_t>::max())); }

}  // namespace

ViewBuffers render_view_buffers(const Scene& scene, const Accel& accel, const Camera& camera, int width, int height,
                                const ViewBufferRequest& request, unsigned threads) {
    if (width < 1 || height < 1 || width > Image::kMaxSide || height > Image::kMaxSide)
        throw Error("image size " + std::to_string(width) + "x" + std::to_string(height) + " is not within 1x1 to " +
                    std::to_string(Image::kMaxSide) + "x" + std::to_string(Image::kMaxSide));
    const size_t pixels = size_t(width) * size_t(height);
    const uint64_t per_pixel = (request.depth ? sizeof(float) : 0) + (request.normal ? sizeof(Vec3) : 0) +
                               (request.counters ? 2 * sizeof(uint32_t) : 0);
    check_memory(uint64_t(pixels) * per_pixel,
                 "the view buffers of a " + std::to_string(width) + "x" + std::to_string(height) + " image");

    ViewBuffers out;
    out.width = width;
    out.height = height;
    if (request.depth) out.depth.assign(pixels, kInfinity);
    if (request.normal) out.normal.assign(pixels, Vec3{});
    if (request.counters) {
        out.nodes.assign(pixels, 0);
        out.prims.assign(pixels, 0);
    }
    std::atomic<uint64_t> hits{0};
    const Tiling tiling{width, height};
    parallel_for(tiling.count(), 1, threads, [&](size_t tile_begin, size_t tile_end) {
        std::vector<Ray> rays;
        std::vector<uint32_t> pixel;
        std::vector<Hit> found;
        uint64_t chunk_hits = 0;
        for (size_t tile = tile_begin; tile < tile_end; ++tile) {
            tile_camera_rays(camera, tiling, tile, pixel, rays);
            trace_tile(accel, rays, found, request.counters, [&](size_t k, const RayCounters& counters) {
                out.nodes[pixel[k]] = saturate32(counters.nodes);
                out.prims[pixel[k]] = saturate32(counters.prims);
            });
            for (size_t k = 0; k < rays.size(); ++k) {
                const Hit& hit = found[k];
                if (!hit.found()) continue;
                ++chunk_hits;
                if (request.depth) out.depth[pixel[k]] = hit.t;
                if (request.normal) {
                    Vec3 n = scene.normal(rays[k], hit);
                    if (dot(n, rays[k].dir) > 0.0f) n = -n;  // the side the camera sees
                    out.normal[pixel[k]] = n;
                }
            }
        }
        hits += chunk_hits;
    });
    out.hits = hits;
    return out;
}

}  // namespace thicket
