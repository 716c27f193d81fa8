// The built-in Cornell box: the geometry of McGuire's CornellBox-Original.obj (public domain;
// Guedis Cardenas and Morgan McGuire, Williams College, 2011), typed in as data so the scene
// needs no file. Vertices are in the OBJ's order and each quad is fanned as (0,1,2), (0,2,3), so
// the triangles are exactly those of loading that OBJ.
#include "thicket/scene/loaders.h"

namespace thicket {
namespace {

// The 18 quads of the OBJ, four corners each, in file order.
constexpr float quad_corners[18][4][3] = {
    // floor
    {{-1.01f, 0.00f, 0.99f}, {1.00f, 0.00f, 0.99f}, {1.00f, 0.00f, -1.04f}, {-0.99f, 0.00f, -1.04f}},
    // ceiling
    {{-1.02f, 1.99f, 0.99f}, {-1.02f, 1.99f, -1.04f}, {1.00f, 1.99f, -1.04f}, {1.00f, 1.99f, 0.99f}},
    // backWall
    {{-0.99f, 0.00f, -1.04f}, {1.00f, 0.00f, -1.04f}, {1.00f, 1.99f, -1.04f}, {-1.02f, 1.99f, -1.04f}},
    // rightWall
    {{1.00f, 0.00f, -1.04f}, {1.00f, 0.00f, 0.99f}, {1.00f, 1.99f, 0.99f}, {1.00f, 1.99f, -1.04f}},
    // leftWall
    {{-1.01f, 0.00f, 0.99f}, {-0.99f, 0.00f, -1.04f}, {-1.02f, 1.99f, -1.04f}, {-1.02f, 1.99f, 0.99f}},
    // shortBox: top, left, front, right, back, bottom
    {{0.53f, 0.60f, 0.75f}, {0.70f, 0.60f, 0.17f}, {0.13f, 0.60f, 0.00f}, {-0.05f, 0.60f, 0.57f}},
    {{-0.05f, 0.00f, 0.57f}, {-0.05f, 0.60f, 0.57f}, {0.13f, 0.60f, 0.00f}, {0.13f, 0.00f, 0.00f}},
    {{0.53f, 0.00f, 0.75f}, {0.53f, 0.60f, 0.75f}, {-0.05f, 0.60f, 0.57f}, {-0.05f, 0.00f, 0.57f}},
    {{0.70f, 0.00f, 0.17f}, {0.70f, 0.60f, 0.17f}, {0.53f, 0.60f, 0.75f}, {0.53f, 0.00f, 0.75f}},
    {{0.13f, 0.00f, 0.00f}, {0.13f, 0.60f, 0.00f}, {0.70f, 0.60f, 0.17f}, {0.70f, 0.00f, 0.17f}},
    {{0.53f, 0.00f, 0.75f}, {0.70f, 0.00f, 0.17f}, {0.13f, 0.00f, 0.00f}, {-0.05f, 0.00f, 0.57f}},
    // tallBox: top, left, back, right, front, bottom
    {{-0.53f, 1.20f, 0.09f}, {0.04f, 1.20f, -0.09f}, {-0.14f, 1.20f, -0.67f}, {-0.71f, 1.20f, -0.49f}},
    {{-0.53f, 0.00f, 0.09f}, {-0.53f, 1.20f, 0.09f}, {-0.71f, 1.20f, -0.49f}, {-0.71f, 0.00f, -0.49f}},
    {{-0.71f, 0.00f, -0.49f}, {-0.71f, 1.20f, -0.49f}, {-0.14f, 1.20f, -0.67f}, {-0.14f, 0.00f, -0.67f}},
    {{-0.14f, 0.00f, -0.67f}, {-0.14f, 1.20f, -0.67f}, {0.04f, 1.20f, -0.09f}, {0.04f, 0.00f, -0.09f}},
    {{0.04f, 0.00f, -0.09f}, {0.04f, 1.20f, -0.09f}, {-0.53f, 1.20f, 0.09f}, {-0.53f, 0.00f, 0.09f}},
    {{-0.53f, 0.00f, 0.09f}, {0.04f, 0.00f, -0.09f}, {-0.14f, 0.00f, -0.67f}, {-0.71f, 0.00f, -0.49f}},
    // light
    {{-0.24f, 1.98f, 0.16f}, {-0.24f, 1.98f, -0.22f}, {0.23f, 1.98f, -0.22f}, {0.23f, 1.98f, 0.16f}},
};

// Materials in the order of CornellBox-Original.mtl, so ids agree with loading OBJ + MTL.
enum Mat : uint32_t { left_wall, right_wall, floor_, ceiling, back_wall, short_box, tall_box, light };

constexpr uint32_t quad_material[18] = {floor_,    ceiling,   back_wall, right_wall, left_wall, short_box,
                                        short_box, short_box, short_box, short_box,  short_box, tall_box,
                                        tall_box,  tall_box,  tall_box,  tall_box,   tall_box,  light};

Material make(const char* name, Vec3 diffuse, float ior, Vec3 emission = {}) {
    Material m;
    m.name = name;
    m.diffuse = diffuse;
    m.specular = {0, 0, 0};
    m.emission = emission;
    m.shininess = 10.0f;  // Ns 10 throughout the .mtl
    m.ior = ior;
    return m;
}

}  // namespace

/// The classic Cornell box: 72 vertices, 36 triangles, 8 materials (the light emits (17,12,4)).
TriangleMesh builtin_cornell_box() {
    TriangleMesh mesh;
    const Vec3 white{0.725f, 0.71f, 0.68f};
    mesh.materials = {
        make("leftWall", {0.63f, 0.065f, 0.05f}, 1.5f),
        make("rightWall", {0.14f, 0.45f, 0.091f}, 1.5f),
        make("floor", white, 1.0f),
        make("ceiling", white, 1.0f),
        make("backWall", white, 1.0f),
        make("shortBox", white, 1.0f),
        make("tallBox", white, 1.0f),
        make("light", {0.78f, 0.78f, 0.78f}, 1.0f, {17.0f, 12.0f, 4.0f}),
    };
    for (uint32_t q = 0; q < 18; ++q) {
        const uint32_t first = uint32_t(mesh.positions.size());
        for (const auto& c : quad_corners[q]) mesh.positions.push_back({c[0], c[1], c[2]});
        const uint32_t tris[6] = {first, first + 1, first + 2, first, first + 2, first + 3};
        mesh.indices.insert(mesh.indices.end(), tris, tris + 6);
        mesh.material_ids.push_back(quad_material[q]);
        mesh.material_ids.push_back(quad_material[q]);
    }
    return mesh;
}

}  // namespace thicket
