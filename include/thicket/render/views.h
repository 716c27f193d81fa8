#pragma once
/// The preview renderer's views: one primary ray per pixel through an Accel, coloured by hit
/// distance, by surface orientation, or by the work the structure did (nodes visited).
#include <cstdint>
#include <string>
#include <string_view>

#include "thicket/accel/accel.h"
#include "thicket/render/camera.h"
#include "thicket/render/image.h"
#include "thicket/scene/scene.h"

namespace thicket {

enum class View {
    Depth,    ///< grey by hit distance: nearest hit in the image white, farthest dark grey; misses black
    Normal,   ///< geometric normal of the hit primitive, faced toward the viewer, as 0.5 * n + 0.5
    Heatmap,  ///< nodes visited per ray on a black-blue-magenta-orange-yellow-white ramp, with a legend
};

/// "depth", "normal" or "heatmap" to View; throws Error naming the bad value and the choices.
View parse_view(std::string_view name);
const char* view_name(View view);

/// Parses `render --size` "WIDTHxHEIGHT": each side in [1, Image::kMaxSide], and the image with
/// its per-pixel buffers must fit in available memory; throws Error quoting the text (and saying
/// how much memory it needs).
void parse_image_size(std::string_view text, int& width, int& height);

struct RenderOptions {
    View view = View::Normal;
    int width = 640, height = 480;
    unsigned threads = 0;    ///< 0: all cores
    double heat_max = 0.0;   ///< heatmap: node count at the top of the ramp; 0: the image's maximum
    bool legend = true;      ///< heatmap: draw the colour-bar legend (when the image is large enough)
    bool progress = true;    ///< show a progress bar on a terminal for renders longer than a second
};

struct RenderStats {
    uint64_t rays = 0;           ///< primary rays traced (one per pixel)
    uint64_t hits = 0;
    double seconds = 0.0;        ///< time spent tracing (not colouring or writing)
    double rays_per_second = 0.0;
    double depth_near = 0.0, depth_far = 0.0;  ///< depth view: hit distances mapped to white and dark grey
    // Heatmap view only (the other views trace without counting):
    double avg_nodes = 0.0;      ///< nodes visited per ray
    double avg_prims = 0.0;      ///< primitives tested per ray
    uint64_t max_nodes = 0;      ///< most nodes any ray visited
    double heat_scale = 0.0;     ///< node count mapped to the ramp's top (heat_max or max_nodes)
    bool legend_drawn = false;
};

/// Renders `scene` through `accel` (built over the same scene) as seen by `camera`. The image is
/// options.width x options.height; rows are traced in parallel. Throws Error on bad options.
Image render_view(const Scene& scene, const Accel& accel, const Camera& camera, const RenderOptions& options,
                  RenderStats* stats = nullptr);

/// The heatmap colour ramp at x in [0, 1] (clamped): black, blue, magenta, orange, yellow, white,
/// with lightness rising monotonically so that more work always reads as brighter.
Vec3 heat_colour(float x);

/// Draws the heatmap legend into the bottom strip of `image`: a black band holding `title`, a
/// colour bar of heat_colour over [0, max_value] and tick labels 0, max/2 and max. Returns false
/// (drawing nothing) when the image is too small to hold it legibly (below about 100 x 44).
bool draw_heat_legend(Image& image, double max_value, std::string_view title = "nodes/ray");

}  // namespace thicket
