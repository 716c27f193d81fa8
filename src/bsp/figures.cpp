// Cell boxes and the figures of a built BSP tree.
#include <algorithm>
#include <cmath>
#include <vector>

#include "fragments.h"
#include "thicket/bsp/build.h"
#include "thicket/core/sah.h"

namespace thicket {

void bsp_cut_box(const Aabb& box, const BspPlane& plane, Aabb& back, Aabb& front) {
    back = front = Aabb{};
    if (box.empty()) return;
    // The part of a box on one side of a plane projects onto each axis exactly: along axis a,
    // n_a x_a is bounded by the offset minus the least (back side) or greatest (front side)
    // that the other two terms n_b x_b can contribute within the box.
    double n[3], lo[3], hi[3], least = 0.0, most = 0.0;
    for (int a = 0; a < 3; ++a) {
        n[a] = double(plane.normal[a]);
        lo[a] = std::min(n[a] * double(box.min[a]), n[a] * double(box.max[a]));
        hi[a] = std::max(n[a] * double(box.min[a]), n[a] * double(box.max[a]));
        least += lo[a];
        most += hi[a];
    }
    const double d = double(plane.offset);
    for (int side = 0; side < 2; ++side) {
        // Back: n.x <= d, reachable iff least <= d; front: n.x >= d, iff most >= d.
        if (side == 0 ? least > d : most < d) continue;
        double bmin[3], bmax[3];
        for (int a = 0; a < 3; ++a) {
            bmin[a] = box.min[a];
            bmax[a] = box.max[a];
            if (n[a] == 0.0) continue;
            const double bound = (d - (side == 0 ? least - lo[a] : most - hi[a])) / n[a];
            // Back with n_a > 0 and front with n_a < 0 bound x_a from above; the others from below.
            if ((side == 0) == (n[a] > 0.0))
                bmax[a] = std::min(bmax[a], bound);
            else
                bmin[a] = std::max(bmin[a], bound);
        }
        // To nearest: cell boxes serve cost estimates and figures, never correctness.
        const bsp_build::P3 ends[2] = {{bmin[0], bmin[1], bmin[2]}, {bmax[0], bmax[1], bmax[2]}};
        (side == 0 ? back : front) = intersection(bsp_build::points_box(ends, 2), box);
    }
}

Aabb bsp_cut_box(const Aabb& box, const BspPlane& plane, bool front) {
    Aabb b, f;
    bsp_cut_box(box, plane, b, f);
    return front ? f : b;
}

BspFigures bsp_figures(const BspData& bsp) {
    return walk_tree(!bsp.nodes.empty(), bsp.bounds,
                     [&](const TreeWalkItem& item, double, auto push) -> std::optional<size_t> {
                         const BspNode& node = bsp.nodes[item.node];
                         if (node.is_leaf()) return node.leaf_size();
                         Aabb back, front;
                         bsp_cut_box(item.box, node.plane, back, front);
                         push({node.index, item.depth + 1, back});
                         push({node.index + 1, item.depth + 1, front});
                         return std::nullopt;
                     });
}

}  // namespace thicket
