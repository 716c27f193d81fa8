#pragma once
/// A scene: what acceleration structures are built over. It holds triangles (one mesh) and
/// shapes (spheres, tori, ...). Primitive ids count primitives in file order: a mesh contributes
/// its triangles in order (polygons fan-triangulated in order), every other shape one id, so the
/// ids of a JSON scene interleave triangles and shapes. Scenes without shapes (every mesh
/// format) have ids equal to triangle indices.
///
/// Geometries group the ids by what added them: each add_mesh / add_shape / add_shapes call is
/// one geometry, numbered in call order, holding a contiguous range of ids (Open3D's
/// add_triangles and geometry_ids, Embree's geometries). The structures see only primitive ids;
/// a front end asks geometry_of() to report which geometry a hit or closest point is on.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "thicket/core/ray.h"
#include "thicket/geometry/mesh.h"
#include "thicket/geometry/prim_runs.h"
#include "thicket/scene/instance.h"
#include "thicket/prims/shapes.h"

namespace thicket {

/// The primitive ids [first, first + count) that one add_* call appended; its index in
/// Scene::geometries is its id. A mesh geometry also owns the vertices
/// mesh.positions[vertex_first, vertex_first + vertex_count) (what Scene::set_vertices moves);
/// a shape geometry owns none.
struct Geometry {
    uint32_t first = 0;
    uint32_t count = 0;
    uint32_t vertex_first = 0;
    uint32_t vertex_count = 0;
};

struct Scene {
    std::string name;    ///< file path or built-in name, for messages
    TriangleMesh mesh;   ///< every triangle, in id order
    std::vector<Shape> shapes;  ///< every shape, in id order
    /// How ids interleave triangles and shapes, ascending. Empty: the triangles' ids come first,
    /// then the shapes' (so a scene filled by assigning mesh and shapes directly is valid).
    std::vector<PrimRun> runs;
    /// Every geometry in id order; their ranges are adjacent and ascending and cover every id.
    /// Empty: one geometry (id 0) holds every primitive, so a scene filled by assigning mesh and
    /// shapes directly is valid.
    std::vector<Geometry> geometries;

    /// Instances of the geometries (two-level instancing, instances/instances.h). Empty: the
    /// geometries are the scene, as always. Otherwise the geometries are prototypes, drawn only
    /// where instances place them: build_accel() builds an instanced structure (InstancedAccel)
    /// whose hits' `prim` are flattened ids (flatten_instances()), which normal() understands.
    /// Fill it with add_instance().
    std::vector<Instance> instances;
    /// instances.size() + 1 entries once there are instances: the flattened id of each instance's
    /// first primitive, then the total (add_instance() keeps it).
    std::vector<uint64_t> instance_first;

    size_t primitive_count() const { return mesh.triangle_count() + shapes.size(); }
    bool has_shapes() const { return !shapes.empty(); }
    /// Bounds of every triangle and shape (empty box for an empty scene); with instances, of every
    /// instance in the world (the prototypes where no instance places them are not drawn).
    Aabb bounds() const;
    /// The triangle or shape behind primitive id `prim` (< primitive_count()).
    PrimRef locate(uint32_t prim) const;

    /// Unit geometric normal at the hit `hit` of `ray` on primitive hit.prim: a triangle's face
    /// normal in its winding order, a shape's outward normal at ray.org + hit.t * ray.dir and the
    /// hit's (u, v). The zero vector where none is defined (zero-area triangle, bad id). In a
    /// scene with instances hit.prim is a flattened id and the normal the world one (the
    /// prototype's carried by the inverse transpose, a triangle's flipped by a mirroring transform).
    Vec3 normal(const Ray& ray, const Hit& hit) const;
    /// Unnormalized face normal of a triangle primitive in its winding order; zero for a shape
    /// (use normal()).
    Vec3 geometric_normal(uint32_t prim) const;

    /// Appends a mesh's triangles (with their materials) as the next ids, in order, as a new
    /// geometry; returns its id.
    uint32_t add_mesh(const TriangleMesh& m);
    /// Appends one shape as the next id, as a new geometry; returns its id.
    uint32_t add_shape(const Shape& s);
    /// Appends shapes as the next ids, in order, as one new geometry (a set of Bezier patches,
    /// of spheres); returns its id.
    uint32_t add_shapes(std::span<const Shape> s);

    /// Number of geometries: geometries.size(), or 1 when that is empty and the scene is not.
    size_t geometry_count() const;
    /// The id range of geometry `id` (< geometry_count()).
    Geometry geometry(uint32_t id) const;
    /// Moves the vertices of mesh geometry `id` (same topology: its triangles keep their indices)
    /// to `positions`, one per vertex the geometry owns (Geometry::vertex_count), in the order it
    /// was added. Structures built before see the move after Accel::refit(scene) (or a rebuild).
    /// Throws Error naming the scene and the geometry, leaving the scene unchanged, for an id out
    /// of range, a geometry without vertices (shapes), a wrong count or a non-finite coordinate.
    void set_vertices(uint32_t id, std::span<const Vec3> positions);

    /// Appends an instance of geometry `geometry` under `transform`; returns its id. Throws Error
    /// naming the scene and the instance for a geometry out of range or a transform that
    /// checked_inverse() refuses (near-singular, non-finite), leaving the scene unchanged.
    uint32_t add_instance(uint32_t geometry, const Affine& transform);
    /// Primitives of every instance: the flattened scene's primitive count (0 without instances).
    uint64_t instanced_primitive_count() const { return instance_first.empty() ? 0 : instance_first.back(); }

    /// Id of the geometry that holds primitive `prim`; kNoPrim for prim >= primitive_count()
    /// (a miss stays a miss).
    uint32_t geometry_of(uint32_t prim) const;

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
