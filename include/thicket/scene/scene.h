#pragma once
/// A scene: what acceleration structures are built over. It holds triangles (one mesh) and
/// shapes (spheres, tori, ...). Primitive ids count primitives in file order: a mesh contributes
/// its triangles in order (polygons fan-triangulated in order), every other shape one id, so the
/// ids of a JSON scene interleave triangles and shapes. Scenes without shapes (every mesh
/// format) have ids equal to triangle indices.
#include <cstdint>
#include <string>
#include <vector>

#include "thicket/core/ray.h"
#include "thicket/geometry/mesh.h"
#include "thicket/geometry/prim_runs.h"
#include "thicket/prims/shapes.h"

namespace thicket {

struct Scene {
    std::string name;    ///< file path or built-in name, for messages
    TriangleMesh mesh;   ///< every triangle, in id order
    std::vector<Shape> shapes;  ///< every shape, in id order
    /// How ids interleave triangles and shapes, ascending. Empty: the triangles' ids come first,
    /// then the shapes' (so a scene filled by assigning mesh and shapes directly is valid).
    std::vector<PrimRun> runs;

    size_t primitive_count() const { return mesh.triangle_count() + shapes.size(); }
    bool has_shapes() const { return !shapes.empty(); }
    /// Bounds of every triangle and shape (empty box for an empty scene).
    Aabb bounds() const;
    /// The triangle or shape behind primitive id `prim` (< primitive_count()).
    PrimRef locate(uint32_t prim) const;

    /// Unit geometric normal at the hit `hit` of `ray` on primitive hit.prim: a triangle's face
    /// normal in its winding order, a shape's outward normal at ray.org + hit.t * ray.dir and the
    /// hit's (u, v). The zero vector where none is defined (zero-area triangle, bad id).
    Vec3 normal(const Ray& ray, const Hit& hit) const;
    /// Unnormalized face normal of a triangle primitive in its winding order; zero for a shape
    /// (use normal()).
    Vec3 geometric_normal(uint32_t prim) const;

    /// Appends a mesh's triangles (with their materials) as the next ids, in order.
    void add_mesh(const TriangleMesh& m);
    /// Appends one shape as the next id.
    void add_shape(const Shape& s);

    /// 64-bit fingerprint of the geometry (FNV-1a over every triangle's vertex bits, then every
    /// shape's type and parameters and the id order), so saved structures can refuse to be used
    /// with another scene. A scene without shapes has the fingerprint it always had.
    uint64_t fingerprint() const;
};

/// Loads a scene from a PLY, OBJ, glTF (.gltf/.glb) or JSON scene (.json, docs/shapes.md) file,
/// or a built-in name (`cornell`; `teapot-patches`: the 32 Bezier patches of the Utah teapot).
/// Throws thicket::Error naming the file and what is wrong.
Scene load_scene(const std::string& path_or_builtin);

/// Names of the built-in scenes, for --help texts.
const char* builtin_scene_names();

}  // namespace thicket
