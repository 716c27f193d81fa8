#pragma once
// The one Wavefront OBJ (and MTL) reader, shared by the mesh loader and the subdivision-cage
// loader. Strict on what Thicket uses (vertices, faces, materials): every number, index and face
// is checked and any other content is an error naming the file and line; statements that only
// carry what Thicket ignores (texture coordinates, normals, groups, free-form geometry) are skipped.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "thicket/geometry/mesh.h"

namespace thicket::obj {

struct ObjData {
    std::vector<Vec3> positions;
    std::vector<uint32_t> face_sizes;     ///< vertices of each face, in file order (no limit but memory)
    std::vector<uint32_t> indices;        ///< 0-based, every one < positions.size()
    std::vector<int32_t> face_materials;  ///< per face: index into materials, or -1 (none named or unknown)
    std::vector<Material> materials;      ///< of every mtllib, in file order
    std::vector<std::string> warnings;    ///< a missing .mtl, an unknown usemtl: the geometry stands
};

/// Parses the OBJ text `text` of file `path` (for messages and to find its .mtl files, which are
/// read when `materials` is true). Throws Error("<path>: line N: ...").
ObjData parse_obj(std::string_view text, const std::string& path, bool materials);

/// Reads and parses an OBJ file (a regular file only: util/input_file.h).
ObjData read_obj(const std::string& path, bool materials);

/// Parses MTL text; appends its materials. Throws Error("<path>: line N: ...").
void parse_mtl(std::string_view text, const std::string& path, std::vector<Material>& out);

}  // namespace thicket::obj
