#pragma once
/// The light-transport integrators: `path` (unidirectional path tracing with next event
/// estimation and BSDF sampling combined by multiple importance sampling, Russian roulette) and
/// `whitted` (recursive mirror reflection and refraction with hard shadows, as in 1980). Both
/// return linear radiance per pixel; film.h turns it into a PNG.
///
/// Determinism: the random numbers of sample s of pixel p come from Rng::for_sample(seed, p, s)
/// alone, the image is cut into fixed tiles whatever the thread count, and each pixel's samples
/// are summed in sample order, so an image is bit-identical for a given seed on any thread count.
#include <cstdint>
#include <string_view>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/render/camera.h"
#include "thicket/render/render_scene.h"

namespace thicket {

enum class Integrator { Path, Whitted };
/// "path" or "whitted"; throws Error naming the bad value and the choices.
Integrator parse_integrator(std::string_view name);
const char* integrator_name(Integrator integrator);

/// Which estimators of direct light the path tracer adds up (all three converge to the same image).
enum class LightStrategy {
    Mis,       ///< light sampling and BSDF sampling, weighted by the power heuristic
    LightOnly, ///< next event estimation only (emitters found by BSDF sampling count only after delta bounces)
    BsdfOnly,  ///< BSDF sampling only: emitters count when a path hits them (point lights are never found)
};

struct TraceOptions {
    int width = 640, height = 480;
    uint32_t spp = 16;           ///< samples per pixel (>= 1)
    uint32_t first_sample = 0;   ///< index of the first sample (progressive rendering continues a run)
    uint64_t seed = 0;
    unsigned threads = 0;        ///< 0: all cores
    uint32_t max_depth = 64;     ///< path segments at most (Russian roulette ends most far sooner)
    uint32_t rr_depth = 3;       ///< segments before Russian roulette starts
    LightStrategy strategy = LightStrategy::Mis;
    bool progress = true;        ///< a progress bar on a terminal for long renders
    bool variance = false;       ///< also estimate each pixel's per-sample luminance variance
};

struct TraceResult {
    int width = 0, height = 0;
    uint32_t spp = 0;
    std::vector<Vec3> radiance;      ///< mean radiance per pixel, row 0 at the top
    std::vector<double> sum;         ///< per pixel: sum of the samples' R, G, B (3 per pixel)
    std::vector<double> lum_sum2;    ///< with `variance`: per pixel, sum of squared sample luminance
    std::vector<float> lum_variance; ///< with `variance`: unbiased per-sample luminance variance
    uint64_t rays = 0;               ///< every ray traced: camera, bounce and shadow rays
    double seconds = 0.0;
};

/// Renders `rs` through `accel` (built over rs.scene) as seen by `camera` with integrator
/// `integrator`. Throws Error on bad options (size, zero spp, no scene).
TraceResult trace_image(const RenderScene& rs, const Accel& accel, const Camera& camera, Integrator integrator,
                        const TraceOptions& options);

/// The path tracer: every path of a tile advances one segment per batch call (accel.intersect),
/// then the tile's shadow rays go as one batch (accel.occluded).
TraceResult trace_path(const RenderScene& rs, const Accel& accel, const Camera& camera, const TraceOptions& options);
/// The Whitted ray tracer: per pixel sample, recursion over mirror and glass (depth limit
/// options.max_depth, at most 16), direct light from every light with one shadow ray each (area
/// lights from their centre, as point lights of their power).
TraceResult trace_whitted(const RenderScene& rs, const Accel& accel, const Camera& camera, const TraceOptions& options);

/// Adds the samples of `more` (rendered with the same size and seed, later sample indices) to
/// `total`, updating the means; used for progressive rendering. Throws Error on a size mismatch.
void accumulate(TraceResult& total, const TraceResult& more);

}  // namespace thicket
