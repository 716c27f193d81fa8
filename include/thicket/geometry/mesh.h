#pragma once
/// Indexed triangle mesh with optional per-triangle materials (kept from OBJ .mtl files for the renderer).
#include <cstdint>
#include <string>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/vec3.h"

namespace thicket {

struct Material {
    std::string name;
    Vec3 diffuse{0.8f, 0.8f, 0.8f};
    Vec3 specular{0.0f, 0.0f, 0.0f};
    Vec3 emission{0.0f, 0.0f, 0.0f};
    float shininess = 0.0f;
    float ior = 1.0f;
    float dissolve = 1.0f;  ///< MTL `d`: 1 opaque, below 1 (partly) transparent
    int illum = -1;         ///< MTL `illum` model number; -1 when the file gives none
};

struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<uint32_t> indices;            ///< 3 per triangle, 0-based into positions
    std::vector<uint32_t> material_ids;       ///< empty, or one per triangle into materials
    std::vector<Material> materials;
    /// Empty, or one per position: the coordinates in double as the source gave them (a PLY with
    /// `double` vertex properties, float64 arrays from Python), which `precision=double`
    /// structures read. `positions` then holds the same points rounded to float, so every float
    /// structure works on the scene unchanged.
    std::vector<Vec3d> positions_double;

    size_t triangle_count() const { return indices.size() / 3; }
    Vec3 vertex(size_t tri, int corner) const { return positions[indices[3 * tri + corner]]; }
    /// Vertex `corner` of triangle `tri` in double: the source's double coordinates when the mesh
    /// has them, else the float position widened exactly.
    Vec3d vertex_double(size_t tri, int corner) const {
        const uint32_t i = indices[3 * tri + corner];
        return positions_double.empty() ? Vec3d(positions[i]) : positions_double[i];
    }
    Aabb bounds() const {
        Aabb b;
        for (uint32_t i : indices) b.grow(positions[i]);
        return b;
    }
};

}  // namespace thicket
