#pragma once
// glTF materials, read from the file's JSON itself rather than from tinygltf's model: tinygltf
// replaces a factor of the wrong type or length by its default without a word, and the values
// must go through the material table (thicket/scene/material_ranges.h) like every other format's.
#include <string>
#include <string_view>
#include <vector>

#include "thicket/geometry/mesh.h"

namespace thicket::gltf {

/// The JSON text of a glTF file's bytes: the whole file for .gltf, the first (JSON) chunk of a
/// .glb. Throws Error("<path>: ...") when a .glb's header or first chunk is malformed.
std::string_view json_text(std::string_view bytes, bool glb, const std::string& path);

/// The materials of the glTF JSON `text`, in file order, mapped to Thicket's MTL-style Material
/// (docs/rendering.md). Throws Error("<path>: materials[i].<property>: ...") for a property of the
/// wrong type or length, or a value the material table refuses.
std::vector<Material> read_materials(std::string_view text, const std::string& path);

/// read_materials()'s error for the file `bytes`, or "" when its materials are fine or its JSON
/// cannot be found or parsed (then the glTF parser's own message is the one to give).
std::string material_error(std::string_view bytes, bool glb, const std::string& path);

}  // namespace thicket::gltf
