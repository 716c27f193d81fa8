#pragma once
/// The renderer's part of a JSON scene (docs/shapes.md, "Materials, lights and camera"): the
/// top-level `materials` (by name), `lights` and `camera`, and each shape's `material`.
#include <string>

#include "thicket/render/render_scene.h"

namespace thicket {

/// Reads `path` (the JSON file `rs.scene` was loaded from) and applies its materials, lights and
/// camera to `rs`. With any shape `material`, the scene is loaded once more to learn which ids each
/// entry made. A file without them leaves `rs` as it is. Throws
/// Error naming the file, the key and what is wrong (an unknown material name, a malformed colour).
void apply_json_render_settings(const std::string& path, RenderScene& rs);

}  // namespace thicket
