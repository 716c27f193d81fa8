#pragma once
/// What the light-transport integrators need beyond the geometry: a material for every
/// primitive, the point lights, and the scene's own camera when it has one. The geometry stays in
/// the Scene (and the Accel built over it); this only points at it.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "thicket/render/bsdf.h"
#include "thicket/render/camera.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// An isotropic point light: radiant intensity `intensity` (W/sr per channel) at `position`.
struct PointLight {
    Vec3 position;
    Vec3 intensity{1.0f};
};

struct RenderScene {
    const Scene* scene = nullptr;             ///< the geometry (must outlive this)
    std::vector<SurfaceMaterial> materials;   ///< materials[0] is the default
    std::vector<uint32_t> prim_material;      ///< one index into materials per primitive id
    std::vector<PointLight> point_lights;
    std::optional<Camera> camera;             ///< the scene's own view, if it has one

    /// The material of primitive `prim` (< scene->primitive_count(); in a scene with instances a
    /// flattened id, whose prototype primitive's material it is).
    const SurfaceMaterial& material(uint32_t prim) const {
        if (scene && !scene->instances.empty()) prim = prototype_prim(prim);
        return materials[prim_material[prim]];
    }
    /// The prototype scene's id of the flattened id `prim` (< scene->instanced_primitive_count()).
    uint32_t prototype_prim(uint32_t prim) const {
        const std::vector<uint64_t>& first = scene->instance_first;
        const size_t i = size_t(std::upper_bound(first.begin(), first.end(), uint64_t(prim)) - first.begin()) - 1;
        return scene->geometry(scene->instances[i].geometry).first + uint32_t(prim - first[i]);
    }
};

/// Materials for `scene`: each triangle's mesh material mapped by surface_from_material(), every
/// shape (and every triangle without a material) the default Lambertian of albedo 0.8. Gives the
/// built-in `cornell` scene (recognised by its name) its standard camera.
RenderScene make_render_scene(const Scene& scene);

/// The Cornell box's standard view: from (0, 1, 3.5) at (0, 1, 0), vertical fov 45 degrees.
Camera cornell_camera();

/// The lecture's example scene: `count` diffuse spheres of random colour and size scattered by
/// `seed` over a ground square (two triangles, primitive ids 0 and 1), with `lights` small
/// spherical area lights above them (the last `lights` shapes). The same
/// (count, lights, seed) always gives the same scene. Throws Error if count is 0, lights > 64, the
/// ids would pass 2^32 - 1, or the scene (and a structure over it) would not fit in memory
/// (check_memory, before allocating).
struct SpheresScene {
    Scene scene;
    std::vector<SurfaceMaterial> materials;
    std::vector<uint32_t> prim_material;
    Camera camera{{0, 1, 1}, {0, 0, 0}};
};
SpheresScene make_spheres_scene(uint32_t count, uint32_t lights, uint64_t seed);
/// make_spheres_scene()'s result as a RenderScene pointing at its scene.
RenderScene render_scene_of(const SpheresScene& s);

}  // namespace thicket
