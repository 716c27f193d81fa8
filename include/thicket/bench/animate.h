#pragma once
/// `thicket bench --animate`: a scene moved frame by frame (same topology), each structure kept up
/// to date by refit (Accel::refit, Embree's RTC_BUILD_QUALITY_REFIT) beside a rebuild of the same
/// structure on the same frame, with what refit saves (time) and what it costs (SAH, Mrays/s).
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "thicket/bench/ray_sets.h"
#include "thicket/bench/tracer.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// How the vertices move over the sequence (phase 0 at rest, 1 at the last frame).
enum class AnimateMotion {
    /// Turned about the vertical (y) axis through the bounds' centre by an angle growing along x,
    /// up to a quarter turn at the ends, and sagging in y: a smooth deformation, neighbours stay
    /// neighbours.
    Bend,
    /// Scaled away from the centre by up to 2x, every vertex also jittered by up to 5% of the
    /// scene's size in a direction of its own: triangles stretch and cross, the worst case for a
    /// tree whose topology is kept.
    Explode,
};

/// "bend" or "explode"; throws Error naming the value otherwise.
AnimateMotion parse_animate_motion(std::string_view text);
const char* animate_motion_name(AnimateMotion motion);

/// Where the vertices `rest` (of a scene with bounds `bounds`) are at `phase` in [0, 1]; the
/// same every run (the jitter is a hash of the vertex index).
std::vector<Vec3> animated_positions(std::span<const Vec3> rest, const Aabb& bounds, AnimateMotion motion,
                                     double phase);

/// `rest` with every mesh geometry's vertices at frame `frame` of `frames` (phase frame/frames).
Scene animated_frame(const Scene& rest, AnimateMotion motion, int frame, int frames);

struct AnimateOptions {
    int frames = 8;                ///< frames after the rest pose (1..1000)
    AnimateMotion motion = AnimateMotion::Bend;
    int reps = 3;                  ///< timed refits, rebuilds and trace passes per frame (median)
    unsigned threads = 0;          ///< 0: all cores
    std::vector<std::string> sets = {"primary"};
    RaySetOptions rays;            ///< image size, camera (fixed over the frames: the rest pose's view)
};

/// One tracer on one frame: the refitted build against a fresh build of the same frame.
struct AnimateRow {
    int frame = 0;
    std::string tracer;
    double refit_ms = 0.0;         ///< median of the timed refits of this frame
    double rebuild_ms = 0.0;       ///< median of the timed builds on this frame
    double sah_refit = 0.0;        ///< 0: the tracer has no SAH figure (Embree)
    double sah_rebuild = 0.0;
    double mrays_refit = 0.0;      ///< all sets' rays over their median pass times together
    double mrays_rebuild = 0.0;
    double agree = 100.0;          ///< % of rays the refitted build answers as the rebuilt one
    size_t rays = 0;
    /// Non-empty when the refit was refused (the message); the refitted tracer was rebuilt on
    /// this frame instead and refits from it onwards.
    std::string refused;
};

/// Runs the sequence: each tracer (which must refit: Tracer::refit) is built on `rest` and
/// refitted frame by frame; per frame a second one is built fresh. `on_row` gets each row as it
/// is done. Throws Error before any frame when a tracer cannot refit.
std::vector<AnimateRow> animate_scene(const Scene& rest, std::span<const TracerFactory> tracers,
                                      const AnimateOptions& options,
                                      const std::function<void(const AnimateRow&)>& on_row = {});

/// The header and one line of the table run_animation prints, and the summary per tracer
/// (medians over the frames, and refit time against embree-refit's when it ran).
std::string animate_header();
std::string format_animate_row(const AnimateRow& row);
std::string format_animate_summary(std::span<const AnimateRow> rows);

}  // namespace thicket
