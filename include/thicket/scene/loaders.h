#pragma once
/// Format-specific loaders behind load_scene(). Each appends to nothing: it returns a fresh mesh
/// (or scene) or throws thicket::Error("<path>: <what is wrong>").
#include <string>

#include "thicket/geometry/mesh.h"
#include "thicket/prims/control_mesh.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// How load_scene() reads a file.
struct LoadOptions {
    /// glTF: one triangle soup with a copy of a mesh for every node that places it, rather than
    /// one geometry with an instance per node (docs/shapes.md, "glTF scenes").
    bool flatten = false;
};

/// load_scene() (scene.h) with `options`: load_scene(path) is load_scene(path, LoadOptions{}).
Scene load_scene(const std::string& path_or_builtin, const LoadOptions& options);

TriangleMesh load_ply(const std::string& path);
/// load_ply() that also gives each face's vertex count in file order: face f (n vertices) is
/// the fan of n - 2 triangles v0 v1 v2, v0 v2 v3, ..., so the polygons can be rebuilt exactly.
TriangleMesh load_ply(const std::string& path, std::vector<uint32_t>& polygon_sizes);
TriangleMesh load_obj(const std::string& path);
TriangleMesh load_gltf(const std::string& path);  ///< .gltf or .glb; node transforms applied, flattened
/// A .gltf or .glb file as load_scene() gives it: a mesh that several nodes place becomes one
/// geometry with an instance per node (its world transform through the node hierarchy), unless
/// `options.flatten` or no mesh is placed twice, when the scene is load_gltf()'s triangle soup
/// (docs/shapes.md, "glTF scenes").
Scene load_gltf_scene(const std::string& path, const LoadOptions& options = {});
TriangleMesh builtin_cornell_box();

/// A mesh file of any mesh format above, chosen by its extension (case-insensitive).
TriangleMesh load_mesh(const std::string& path);
/// A JSON scene of meshes and shapes (docs/shapes.md); errors name the shape and field.
Scene load_json_scene(const std::string& path);
/// The same, also giving where each entry of the file's `shapes` array went: entry i made
/// primitive ids [entry_prims[i], entry_prims[i + 1]) (one more value than entries), so that the
/// renderer can give it its `material`.
Scene load_json_scene(const std::string& path, std::vector<uint32_t>& entry_prims);

/// Reads the polygons of a Wavefront OBJ or a PLY file (by extension) as a subdivision cage (no
/// triangulation; normals, texture coordinates and materials are ignored) and validates it.
/// Vertices no face uses are dropped. Throws Error("<path>: ...").
ControlMesh load_control_mesh(const std::string& path);

}  // namespace thicket
