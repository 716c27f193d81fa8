#pragma once
/// The control mesh ("cage") of a subdivision surface: polygons of any size, kept as polygons.
#include <cstdint>
#include <vector>

#include "thicket/core/vec3.h"

namespace thicket {

struct ControlMesh {
    std::vector<Vec3> positions;
    std::vector<uint32_t> face_sizes;  ///< vertices per face, each >= 3
    std::vector<uint32_t> indices;     ///< face by face, 0-based; counter-clockwise seen from outside

    size_t face_count() const { return face_sizes.size(); }
};

/// Throws Error naming the face, vertex or edge at fault unless the mesh is a consistently
/// oriented 2-manifold (with or without boundary) of finite positions: every face has >= 3
/// distinct in-range vertices, every edge has at most two faces, which traverse it in opposite
/// directions, every vertex's faces form one fan, and every vertex is used by some face.
void validate_control_mesh(const ControlMesh& cage);

/// The cube [-1, 1]^3 as 6 outward quads (8 valence-3 vertices: all extraordinary).
ControlMesh cube_control_mesh();

}  // namespace thicket
