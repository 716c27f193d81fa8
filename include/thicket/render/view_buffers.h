#pragma once
/// The preview views' per-pixel answers before they are coloured: hit distance, faced geometric
/// normal and the work counters of one primary ray per pixel. render_view() turns such answers
/// into an 8-bit picture; a caller that wants the numbers themselves (the Python module's
/// Accel.render, an analysis of where a structure works hard) takes them from here.
#include <cstdint>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/render/camera.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// What render_view_buffers() fills; the others stay empty.
struct ViewBufferRequest {
    bool depth = false;
    bool normal = false;
    bool counters = false;  ///< nodes and prims per pixel (each ray traced alone, with counters)
};

/// Row-major, row 0 at the top (pixel (x, y) at index y * width + x), as the views' images.
struct ViewBuffers {
    int width = 0, height = 0;
    std::vector<float> depth;     ///< hit distance t (camera rays are unit length); +inf on a miss
    std::vector<Vec3> normal;     ///< unit geometric normal turned toward the camera; (0, 0, 0) on a
                                  ///< miss or a zero-area triangle
    std::vector<uint32_t> nodes;  ///< nodes (or cells) the ray visited, saturating at 2^32 - 1
    std::vector<uint32_t> prims;  ///< primitive tests of the ray, saturating likewise
    uint64_t hits = 0;
};

/// Traces one ray per pixel centre of a width x height image from `camera` (Camera::generate at
/// x + 0.5, y + 0.5) through `accel`, built over `scene`, in render_view()'s tiles, and keeps the
/// answers `request` names. `threads`: 0 for every core. The answers do not depend on it.
/// Throws Error for a side outside [1, Image::kMaxSide] or answers that do not fit in memory.
ViewBuffers render_view_buffers(const Scene& scene, const Accel& accel, const Camera& camera, int width, int height,
                                const ViewBufferRequest& request, unsigned threads = 0);

}  // namespace thicket
