// Any-hit recording and the tetra walk's tetrahedra for `thicket explain` and the trace request.
#include "explore_record.h"

#include "explore_as.h"
#include "thicket/bvh/bvh.h"
#include "thicket/grid/grid.h"
#include "thicket/tetra/tetra.h"

namespace thicket::explore {

bool record_any_hit(const Accel& accel, const Ray& ray, TraversalRecorder& rec) {
    bool blocked = false;
    const auto recorded = [&](const auto& s) {
        rec.detailed = true;
        blocked = s.any(ray, rec);
    };
    if (as<Bvh>(accel, recorded) || as<Grid>(accel, recorded) || as<Tetra>(accel, recorded)) return blocked;
    RayCounters counters;
    blocked = accel.occluded(ray, counters);
    rec.nodes += counters.nodes;
    rec.prims += counters.prims;
    rec.detailed = false;
    return blocked;
}

std::optional<std::array<Vec3, 4>> tetrahedron_corners(const Accel& accel, uint32_t id) {
    std::optional<std::array<Vec3, 4>> out;
    as<Tetra>(accel, [&](const auto& s) {
        const TetraMesh& m = s.data().mesh;
        if (id >= m.tet_count()) return;
        std::array<Vec3, 4> c;
        for (int i = 0; i < 4; ++i) {
            const Vec3d& p = m.points[m.tets[size_t(id) * 4 + i]];
            c[i] = Vec3{float(p.x), float(p.y), float(p.z)};
        }
        out = c;
    });
    return out;
}

}  // namespace thicket::explore
