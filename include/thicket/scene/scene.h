#pragma once
/// A scene: what acceleration structures are built over. Primitive ids are triangle indices in
/// file order (polygons fan-triangulated in order).
#include <cstdint>
#include <string>

#include "thicket/scene/mesh.h"

namespace thicket {

struct Scene {
    std::string name;    ///< file path or built-in name, for messages
    TriangleMesh mesh;

    size_t primitive_count() const { return mesh.triangle_count(); }
    Aabb bounds() const { return mesh.bounds(); }
    /// Geometric (unnormalized) normal of a primitive, in its winding order.
    Vec3 geometric_normal(uint32_t prim) const {
        const Vec3 a = mesh.vertex(prim, 0), b = mesh.vertex(prim, 1), c = mesh.vertex(prim, 2);
        return cross(b - a, c - a);
    }
    /// 64-bit fingerprint of the geometry (FNV-1a over every triangle's vertex bits), so saved
    /// structures can refuse to be used with another scene.
    uint64_t fingerprint() const;
};

/// Loads a scene from a PLY, OBJ or glTF (.gltf/.glb) file, or a built-in name (`cornell`).
/// Throws thicket::Error naming the file and what is wrong.
Scene load_scene(const std::string& path_or_builtin);

/// Names of the built-in scenes, for --help texts.
const char* builtin_scene_names();

}  // namespace thicket
