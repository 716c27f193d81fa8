#pragma once
/// Format-specific loaders behind load_scene(). Each appends to nothing: it returns a fresh mesh
/// or throws thicket::Error("<path>: <what is wrong>").
#include <string>

#include "thicket/scene/mesh.h"

namespace thicket {

TriangleMesh load_ply(const std::string& path);
TriangleMesh load_obj(const std::string& path);
TriangleMesh load_gltf(const std::string& path);  ///< .gltf or .glb; node transforms applied
TriangleMesh builtin_cornell_box();

}  // namespace thicket
