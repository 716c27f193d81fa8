// The tetrahedral mesh's drawing (tetra/draw.h): levels by a breadth-first walk across faces
// from the tetrahedra that touch the surface.
#include "thicket/tetra/draw.h"

#include <algorithm>
#include <vector>

namespace thicket {

void draw_nodes(const TetraData& tetra, const DrawnNodeVisitor& visit) {
    const TetraMesh& m = tetra.mesh;
    const size_t n = m.tet_count();
    if (n == 0) return;
    std::vector<uint32_t> level(n, kNoTet), frontier;
    for (uint32_t t = 0; t < n; ++t)
        for (int k = 0; k < 4; ++k)
            if (m.face_tris[4 * t + k] != kNoTet) {
                level[t] = 0;
                frontier.push_back(t);
                break;
            }
    if (frontier.empty()) std::fill(level.begin(), level.end(), 0u);
    for (uint32_t l = 1; !frontier.empty(); ++l) {
        std::vector<uint32_t> next;
        for (uint32_t t : frontier)
            for (int k = 0; k < 4; ++k) {
                const uint32_t o = m.neighbors[4 * t + k];
                if (o != kNoTet && o < n && level[o] == kNoTet) {
                    level[o] = l;
                    next.push_back(o);
                }
            }
        frontier.swap(next);
    }
    for (uint32_t t = 0; t < n; ++t) {
        if (level[t] == kNoTet) continue;  // cut off from the surface: no level to show it at
        DrawnNode d = drawn_box(t, level[t], Aabb{}, false, 0);
        d.shape = DrawnNode::Shape::Tetra;
        for (int k = 0; k < 4; ++k) {
            const Vec3d& p = m.points[m.tets[4 * t + k]];
            d.points.push_back({float(p.x), float(p.y), float(p.z)});
        }
        visit(d);
    }
}

DrawingLegend draw_legend(const TetraData&) {
    return {"tetrahedra", "steps (across faces) from the nearest tetrahedron touching the scene's surface"};
}

}  // namespace thicket
