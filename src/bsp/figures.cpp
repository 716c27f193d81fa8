// Cell boxes and the figures of a built BSP tree.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "fragments.h"
#include "thicket/accel/accel.h"
#include "thicket/bsp/build.h"

namespace thicket {

void bsp_cut_box(const Aabb& box, const BspPlane& plane, Aabb& back, Aabb& front) {
    back = front = Aabb{};
    if (box.empty()) return;
    const Vec3& n = plane.normal;
    const int axis = n.y == 0.0f && n.z == 0.0f ? 0 : (n.x == 0.0f && n.z == 0.0f ? 1 : (n.x == 0.0f && n.y == 0.0f ? 2 : -1));
    if (axis >= 0 && n[axis] != 0.0f) {
        // Axis-aligned: the cut is exact in float.
        const float at = plane.offset / n[axis];
        Aabb lo = box, hi = box;
        lo.max[axis] = std::min(lo.max[axis], at);
        hi.min[axis] = std::max(hi.min[axis], at);
        if (n[axis] < 0.0f) std::swap(lo, hi);
        back = lo.empty() ? Aabb{} : lo;
        front = hi.empty() ? Aabb{} : hi;
        return;
    }
    using bsp_build::P3;
    P3 corner[8];
    double dist[8];
    for (int c = 0; c < 8; ++c) {
        corner[c] = {double((c & 1) ? box.max.x : box.min.x), double((c & 2) ? box.max.y : box.min.y),
                     double((c & 4) ? box.max.z : box.min.z)};
        dist[c] = bsp_build::plane_distance(plane, corner[c]);
    }
    // Bounds of each side: its corners, and where the box's 12 edges cross the plane.
    P3 ends[2][2] = {{{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}},
                     {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}}};
    auto grow = [&](int side, const P3& p) {
        for (int a = 0; a < 3; ++a) {
            ends[side][0][a] = std::min(ends[side][0][a], p[a]);
            ends[side][1][a] = std::max(ends[side][1][a], p[a]);
        }
    };
    for (int c = 0; c < 8; ++c) {
        if (dist[c] <= 0.0) grow(0, corner[c]);
        if (dist[c] >= 0.0) grow(1, corner[c]);
        for (int a = 0; a < 3; ++a) {
            const int d = c | (1 << a);
            if (d == c || !((dist[c] < 0.0 && dist[d] > 0.0) || (dist[c] > 0.0 && dist[d] < 0.0))) continue;
            const double s = dist[c] / (dist[c] - dist[d]);
            P3 q;
            for (int k = 0; k < 3; ++k) q[k] = corner[c][k] + s * (corner[d][k] - corner[c][k]);
            grow(0, q);
            grow(1, q);
        }
    }
    // To nearest: cell boxes serve cost estimates and figures, never correctness.
    if (ends[0][0][0] <= ends[0][1][0]) back = intersection(bsp_build::points_box(ends[0], 2), box);
    if (ends[1][0][0] <= ends[1][1][0]) front = intersection(bsp_build::points_box(ends[1], 2), box);
}

Aabb bsp_cut_box(const Aabb& box, const BspPlane& plane, bool front) {
    Aabb b, f;
    bsp_cut_box(box, plane, b, f);
    return front ? f : b;
}

BspFigures bsp_figures(const BspData& bsp) {
    BspFigures f;
    if (bsp.nodes.empty()) return f;
    const double root_area = bsp.bounds.half_area();
    struct Item {
        uint32_t node;
        size_t depth;
        Aabb cell;
    };
    std::vector<Item> stack{{0, 0, bsp.bounds}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const BspNode& node = bsp.nodes[it.node];
        const double rel = root_area > 0.0 ? double(it.cell.half_area()) / root_area : 1.0;
        ++f.nodes;
        f.max_depth = std::max(f.max_depth, it.depth);
        if (node.is_leaf()) {
            ++f.leaves;
            f.max_leaf_size = std::max<size_t>(f.max_leaf_size, node.leaf_size());
            f.empty_leaves += node.leaf_size() == 0 ? 1 : 0;
            f.sah_cost += rel * kSahIntersectionCost * node.leaf_size();
        } else {
            f.sah_cost += rel * kSahTraversalCost;
            Aabb back, front;
            bsp_cut_box(it.cell, node.plane, back, front);
            stack.push_back({node.index, it.depth + 1, back});
            stack.push_back({node.index + 1, it.depth + 1, front});
        }
    }
    return f;
}

}  // namespace thicket
