// Structural checks of a tetra structure (a loaded file must not make the walk read out of
// bounds or loop): every index in range, the incidence lists well formed, the fallback sorted.
#include <cmath>
#include <string>

#include "thicket/bvh/build.h"
#include "thicket/core/error.h"
#include "thicket/tetra/build.h"
#include "tetra/invalid.h"

namespace thicket {

void validate_tetra(const TetraData& data, size_t primitive_count) {
    const TetraMesh& m = data.mesh;
    const size_t points = m.points.size(), tets = m.tets.size() / 4;
    if (m.tets.size() % 4 != 0 || m.neighbors.size() != m.tets.size() || m.face_tris.size() != m.tets.size())
        invalid_tetra("tetrahedra, neighbours and face triangles are not 4 per tetrahedron");
    for (const Vec3d& p : m.points)
        if (!is_finite(p)) invalid_tetra("a vertex is not finite");
    for (uint32_t v : m.tets)
        if (v >= points) invalid_tetra("vertex id " + std::to_string(v) + " of " + std::to_string(points));
    for (size_t i = 0; i < m.neighbors.size(); ++i) {
        const uint32_t n = m.neighbors[i];
        if (n != kNoTet && n >= tets) invalid_tetra("neighbour id " + std::to_string(n) + " of " + std::to_string(tets));
    }
    if (tets == 0) {
        if (!m.grid_start.empty() || m.grid_res != 0) invalid_tetra("a start grid without tetrahedra");
    } else {
        if (points == 0 || m.vertex_offsets.size() != points + 1 || m.vertex_offsets.front() != 0 ||
            m.vertex_offsets.back() != m.vertex_tris.size())
            invalid_tetra("vertex incidence offsets do not match the vertices");
        for (size_t v = 0; v < points; ++v)
            if (m.vertex_offsets[v] > m.vertex_offsets[v + 1]) invalid_tetra("vertex incidence offsets decrease");
        if (m.grid_res < 1 || m.grid_res > 32 || m.grid_start.size() != size_t(m.grid_res) * m.grid_res * m.grid_res)
            invalid_tetra("start grid of resolution " + std::to_string(m.grid_res) + " with " +
                    std::to_string(m.grid_start.size()) + " cells");
        for (uint32_t t : m.grid_start)
            if (t >= tets) invalid_tetra("start grid names tetrahedron " + std::to_string(t));
        if (!is_finite(m.box_min) || !is_finite(m.box_max) || m.box_min.x > m.box_max.x || m.box_min.y > m.box_max.y ||
            m.box_min.z > m.box_max.z)
            invalid_tetra("box not finite or inverted");
    }
    for (uint32_t p : m.face_tris)
        if (p != kNoTet && p >= primitive_count) invalid_tetra("face triangle id " + std::to_string(p));
    for (uint32_t p : m.vertex_tris)
        if (p >= primitive_count) invalid_tetra("triangle id " + std::to_string(p) + " of " + std::to_string(primitive_count));
    std::vector<uint8_t> covered(primitive_count, 0);
    for (size_t i = 0; i < data.fallback.size(); ++i) {
        const uint32_t p = data.fallback[i];
        if (p >= primitive_count || (i > 0 && p <= data.fallback[i - 1]))
            invalid_tetra("fallback primitive ids out of range or not sorted");
        covered[p] = 1;
    }
    for (uint32_t p : m.vertex_tris) {
        if (covered[p] == 1) invalid_tetra("primitive " + std::to_string(p) + " both meshed and in the fallback");
        covered[p] = 2;
    }
    for (uint32_t p : m.face_tris)
        if (p != kNoTet && covered[p] != 2) invalid_tetra("face triangle " + std::to_string(p) + " not meshed");
    for (size_t p = 0; p < primitive_count; ++p)
        if (!covered[p]) invalid_tetra("primitive " + std::to_string(p) + " neither meshed nor in the fallback");
    validate_bvh(data.fallback_bvh, data.fallback.size());
}

}  // namespace thicket
