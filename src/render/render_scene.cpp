#include "thicket/render/render_scene.h"

#include <cmath>

#include "thicket/core/error.h"
#include "thicket/util/input_file.h"
#include "thicket/render/sampling.h"
#include "thicket/scene/material_ranges.h"

namespace thicket {

RenderScene make_render_scene(const Scene& scene) {
    RenderScene rs;
    rs.scene = &scene;
    rs.materials.push_back(lambert(Vec3{0.8f}));
    const size_t first_mesh_material = rs.materials.size();
    for (const Material& m : scene.mesh.materials) {
        // The readers refuse values outside the material table; a material made in code is held to
        // the same table here rather than rendered as something it does not say.
        if (const std::string why = material_problem(m); !why.empty())
            throw Error("render: material '" + m.name + "': " + why);
        rs.materials.push_back(surface_from_material(m));
    }
    const size_t prims = scene.primitive_count();
    rs.prim_material.assign(prims, 0);
    const bool has_ids = scene.mesh.material_ids.size() == scene.mesh.triangle_count();
    for (uint32_t p = 0; p < prims; ++p) {
        const PrimRef ref = scene.locate(p);
        if (ref.shape || !has_ids) continue;
        const uint32_t id = scene.mesh.material_ids[ref.index];
        if (id < scene.mesh.materials.size()) rs.prim_material[p] = uint32_t(first_mesh_material + id);
    }
    if (scene.name == "cornell") rs.camera = cornell_camera();
    return rs;
}

Camera cornell_camera() { return Camera({0.0f, 1.0f, 3.5f}, {0.0f, 1.0f, 0.0f}, {0, 1, 0}, 45.0f); }

SpheresScene make_spheres_scene(uint32_t count, uint32_t lights, uint64_t seed) {
    if (count == 0) throw Error("spheres scene: the sphere count must be at least 1");
    if (lights > 64) throw Error("spheres scene: at most 64 lights (asked for " + std::to_string(lights) + ")");
    // Primitive ids are 32-bit: the ground's two triangles, the spheres and the lights must fit.
    if (uint64_t(count) + lights + 2 > uint64_t(kNoPrim))
        throw Error("spheres scene: " + std::to_string(count) + " spheres and " + std::to_string(lights) +
                    " lights exceed the 2^32 - 1 primitive ids a scene holds");
    // Each sphere costs its shape, material and id here, and about kStructureBytes more in any
    // structure built over it (nodes, build references): refuse before allocating, not with bad_alloc.
    constexpr uint64_t kStructureBytes = 128;
    const uint64_t per_sphere = sizeof(Shape) + sizeof(SurfaceMaterial) + sizeof(uint32_t) + kStructureBytes;
    check_memory((uint64_t(count) + lights) * per_sphere,
                 "spheres scene: " + std::to_string(count) + " spheres (" + std::to_string(per_sphere) + " bytes each)");
    SpheresScene out;
    Rng rng = Rng::for_sample(seed, 0xC0FFEE, 0);
    // The spheres lie on a square of side proportional to sqrt(count), so density stays the same.
    const float half = 0.6f * std::sqrt(float(count));
    out.materials.push_back(lambert(Vec3{0.6f}));  // the ground
    auto add = [&](Sphere s, const SurfaceMaterial& m) {
        out.materials.push_back(m);
        out.prim_material.push_back(uint32_t(out.materials.size() - 1));
        out.scene.add_shape(s);
    };
    // The ground: a square of two triangles a little larger than the field (a huge sphere would
    // stretch the scene's bounds, and with them every grid's cells, by orders of magnitude).
    TriangleMesh ground;
    const float g = half + 6.0f;
    ground.positions = {{-g, 0.0f, -g}, {-g, 0.0f, g}, {g, 0.0f, g}, {g, 0.0f, -g}};
    ground.indices = {0, 1, 2, 0, 2, 3};  // wound so that the normal is +y
    out.scene.add_mesh(ground);
    out.prim_material = {0, 0};
    for (uint32_t i = 0; i < count; ++i) {
        const float r = 0.15f + 0.25f * rng.uniform();
        const float x = (2.0f * rng.uniform() - 1.0f) * half, z = (2.0f * rng.uniform() - 1.0f) * half;
        const Vec3 colour{0.2f + 0.7f * rng.uniform(), 0.2f + 0.7f * rng.uniform(), 0.2f + 0.7f * rng.uniform()};
        add(Sphere{{x, r, z}, r}, lambert(colour));
    }
    // Lights: small warm-white spheres on a ring above the field, bright enough to light it.
    const float height = 0.8f * half + 3.0f, ring = 0.5f * half;
    for (uint32_t l = 0; l < lights; ++l) {
        const float a = 2.0f * kPi * (float(l) + 0.5f) / float(lights);
        SurfaceMaterial m = lambert(Vec3{0.0f});
        const float radius = 0.05f * half + 0.2f;
        // Radiance so that each light's power lights the field at a similar level whatever its size.
        const float L = 1.6f * height * height / (float(lights) * radius * radius);
        m.emission = Vec3{1.0f, 0.9f, 0.75f} * L;
        m.two_sided = true;
        add(Sphere{{ring * std::cos(a), height, ring * std::sin(a)}, radius}, m);
    }
    out.scene.name = "spheres";
    out.camera = Camera({0.0f, 0.55f * half + 1.5f, 1.35f * half + 2.0f}, {0.0f, 0.0f, 0.15f * half}, {0, 1, 0}, 45.0f);
    return out;
}

RenderScene render_scene_of(const SpheresScene& s) {
    RenderScene rs;
    rs.scene = &s.scene;
    rs.materials = s.materials;
    rs.prim_material = s.prim_material;
    rs.camera = s.camera;
    return rs;
}

}  // namespace thicket
