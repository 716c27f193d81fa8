#pragma once
/// The bench's standard ray sets, generated from a scene by fixed rules and fixed seeds, so that
/// every structure (and every other library, through `thicket rays`) traces the very same rays.
///
/// The view (camera and light) comes first, from the bounds and a probe:
/// - The scene is *interior* when a 32 x 24 probe image from the centre of the bounds, looking along
///   +x (or +z when the bounds are deeper in z than in x) with a 60 degree field of view, hits in at
///   least 90% of its pixels and more than half of those hits are on front faces (counter-clockwise
///   as seen from the centre): the centre stands in an enclosed space such as a hall or an atrium,
///   not inside a closed object (whose inside faces the probe would see from behind).
/// - Camera: the one given; else for an interior scene that probe camera (at the centre, fov 60);
///   else auto_camera() of the bounds (outside, from +z, 10 degrees above), which frames objects.
/// - Light (a point, for the shadow set): for an interior scene, a ray goes straight up (+y) from
///   the centre; if it hits, the light sits three quarters of the way to that ceiling, in the open
///   space under it; otherwise (an open roof, or any other scene) it is above the bounds: centre x
///   and z, half the largest extent over the top.
///
/// Sets (W x H is the image size, default 320 x 240):
/// - primary: one ray per pixel, row by row from the top-left pixel, through the pixel centre, from
///   the camera; tmin 0, tmax inf.
/// - shadow: any-hit. For every primary ray that hits, in pixel order: p = the hit point, n = the
///   hit triangle's unit geometric normal turned to face the incoming ray, o = p + n * offset with
///   offset = surface_offset(bounds). The ray goes from o towards the light L, normalized, with
///   tmax = |L - o| * (1 - 1e-4): just short of the light. Hits whose faced normal points away from
///   the light (dot(n, L - p) <= 0) get no ray: a renderer knows them to be unlit without tracing.
///   Neither do hits on degenerate triangles.
/// - diffuse: closest hit. For every primary hit, in pixel order: the same origin o, a
///   cosine-weighted direction in n's hemisphere (sample_cosine_hemisphere(), PCG32 seed
///   kDiffuseSeed); tmin 0, tmax inf.
/// - random: closest hit, W x H rays: origins uniform in the scene's bounds (x, then y, then z
///   drawn), directions uniform on the sphere (sample_unit_sphere()), PCG32 seed kRandomSeed;
///   tmin 0, tmax inf. An empty scene gets none.
/// The probe and the primary hits that shadow and diffuse rays start from come from the `bvh`
/// structure with its default options (kRaySetHitSpec), whatever structures are being measured.
/// Bytes are identical for the same scene, size and camera on any IEEE-754 machine, as long as the
/// compiler does not contract a * b + c into FMAs (e.g. -march=native builds may differ).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/render/camera.h"
#include "thicket/scene/scene.h"

namespace thicket {

inline constexpr uint64_t kDiffuseSeed = 0x7468696b64696666ULL;  // "thikdiff"
inline constexpr uint64_t kRandomSeed = 0x7468696b72616e64ULL;   // "thikrand"
/// Structure whose primary hits the shadow and diffuse sets start from.
inline constexpr const char* kRaySetHitSpec = "bvh";

struct RaySet {
    std::string name;          ///< primary, shadow, diffuse or random
    bool any_hit = false;      ///< traced with occluded() (shadow) rather than intersect()
    std::vector<Ray> rays;
    std::vector<uint32_t> source;  ///< shadow, diffuse: index of the primary ray each ray starts at
    bool coherent = false;     ///< consecutive rays are neighbours (primary: along a row)
};

struct RaySetOptions {
    int width = 320;
    int height = 240;
    std::optional<Camera> camera;  ///< none: auto_camera() of the scene's bounds
};

/// The set names in their standard order: primary, shadow, diffuse, random.
const std::vector<std::string>& ray_set_names();
/// Parses a comma-separated list of set names (duplicates dropped, order kept); throws Error
/// naming an unknown set and listing the known ones.
std::vector<std::string> parse_ray_set_list(std::string_view text);

/// Parses "WIDTHxHEIGHT" (e.g. 320x240) into options.width and options.height; throws Error
/// quoting the text when it is malformed or a side is outside [1, 16384].
/// Also throws Error "... needs N GiB of memory" when ray_set_bytes() exceeds what is available.
void parse_ray_set_size(std::string_view text, RaySetOptions& options);
/// Bytes generate_ray_sets() needs at most for options.width x options.height (all four sets).
uint64_t ray_set_bytes(const RaySetOptions& options);

/// Camera and light of the sets, by the rules above.
struct RaySetView {
    Camera camera;
    Vec3 light;
    bool interior = false;  ///< the probe found the centre of the bounds in an enclosed space
};
RaySetView ray_set_view(const Scene& scene, const Accel& hits_from, const RaySetOptions& options);

/// The light position for scenes that are not interior: above the centre of the bounds, by half
/// the largest extent over the top (+y, the cameras' up), open space whatever the scene holds.
Vec3 light_above_bounds(const Aabb& bounds);
/// How far secondary rays start off the surface: 1e-4 of the scene's scale (the larger of its
/// largest extent and its largest coordinate magnitude), so it stays clear of float rounding.
float surface_offset(const Aabb& bounds);

/// Generates the named sets, in the order given, seen from `view` (from ray_set_view()).
/// `hits_from` answers the primary rays that shadow and diffuse rays start from (pass a
/// kRaySetHitSpec structure for the standard sets).
/// `threads` only speeds up tracing the primary rays; the output never depends on it.
/// Throws Error for an unknown name or a size outside [1, 16384].
std::vector<RaySet> generate_ray_sets(const Scene& scene, const Accel& hits_from, const RaySetView& view,
                                      std::span<const std::string> names, const RaySetOptions& options,
                                      unsigned threads = 0);
/// The same with the view of ray_set_view(scene, hits_from, options).
std::vector<RaySet> generate_ray_sets(const Scene& scene, const Accel& hits_from,
                                      std::span<const std::string> names, const RaySetOptions& options,
                                      unsigned threads = 0);

/// Rays in the `thicket trace` layout: N rows of ox oy oz dx dy dz tmin tmax.
std::vector<float> ray_matrix(std::span<const Ray> rays);

}  // namespace thicket
