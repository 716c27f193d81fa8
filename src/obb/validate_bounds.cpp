// The OBB tree's load-time proof beyond structure: every box encloses the points of every
// primitive below it, so culling a box the ray misses never loses a hit. (The builder fits each
// node to its own points, so a child's box may stick out of its parent's: containment of the
// children's boxes is neither true nor needed; containment of the subtree's points is.)
//
// The tolerance. The builder measures each half extent in float as the largest
// |dot(axis, p - center)| over the node's points m, then stores half = m * (1 + 1e-5) + margin,
// margin = 4e-6 * scale (scale: the scene's largest coordinate magnitude or extent). Here the
// same quantity q is computed in double from the stored float axes and centre. The float
// measurement differs from q by at most about 7 units of 2^-24 times |p - center| (one rounding
// per coordinate of the difference, three products and two sums), and |p - center| <= 3 * scale
// (the centre lies in the box around the points), so by less than 1.3e-6 * scale. The proof
// asks for half of the builder's growth:
//     half >= |q| * (1 + 5e-6) + 2e-6 * scale,
// which every box the builder wrote meets with at least 0.7e-6 * scale to spare (5e-6 |q| of
// the relative part and 2e-6 * scale of the absolute part are left for that rounding), and which
// keeps at least half the margin the builder gives the traversal's change of frame.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/obb/build.h"

namespace thicket {

namespace {

/// How far the point p lies beyond node b's box with the load-time allowance (> 0: outside), and
/// along which of the box's axes; NaN coordinates give no excess (such a primitive is never hit).
double excess(const ObbNode& b, const Vec3& p, double scale, int& along) {
    const double v[3] = {double(p.x) - b.center.x, double(p.y) - b.center.y, double(p.z) - b.center.z};
    double worst = -INFINITY;
    for (int k = 0; k < 3; ++k) {
        const Vec3& a = b.axis[k];
        const double q = std::fabs(a.x * v[0] + a.y * v[1] + a.z * v[2]);
        const double over = q * (1.0 + 5e-6) + 2e-6 * scale - double(b.half[k]);
        if (over > worst) {
            worst = over;
            along = k;
        }
    }
    return worst;
}

}  // namespace

void validate_obb_bounds(const ObbData& obb, const ObbPoints& points, float scale) {
    if (obb.nodes.empty()) return;
    if (points.offsets.size() != obb.prim_indices.size() + 1)
        throw Error("invalid OBB tree: " + std::to_string(points.offsets.size()) + " point offsets for " +
                    std::to_string(obb.prim_indices.size()) + " primitives");
    // Parents (validate_obb proved every node has at most one and children come after it).
    std::vector<uint32_t> parent(obb.nodes.size(), UINT32_MAX), leaves;
    std::vector<uint32_t> stack{0};
    while (!stack.empty()) {
        const uint32_t n = stack.back();
        stack.pop_back();
        const ObbNode& node = obb.nodes[n];
        if (node.is_leaf()) {
            leaves.push_back(n);
            continue;
        }
        for (uint32_t c : {node.leftFirst, node.leftFirst + 1}) {
            parent[c] = n;
            stack.push_back(c);
        }
    }
    // Each leaf's points against the leaf and every ancestor: the subtree's points of each box.
    const double s = std::isfinite(scale) ? double(scale) : 0.0;
    for (uint32_t leaf : leaves) {
        const ObbNode& l = obb.nodes[leaf];
        for (uint32_t i = l.leftFirst; i < l.leftFirst + l.count; ++i) {
            const uint32_t prim = obb.prim_indices[i];
            for (uint32_t k = points.offsets[prim]; k < points.offsets[prim + 1]; ++k) {
                const Vec3 p = points.points[k];
                for (uint32_t n = leaf; n != UINT32_MAX; n = parent[n]) {
                    int along = 0;
                    const double out = excess(obb.nodes[n], p, s, along);
                    if (out > 0) {
                        char text[96];
                        std::snprintf(text, sizeof text, "%.6g", out);
                        throw Error("invalid OBB tree: node " + std::to_string(n) + "'s box does not contain primitive " +
                                    std::to_string(prim) + " (a point of it lies " + text + " beyond the box along its axis " +
                                    std::to_string(along) + ", margin included)");
                    }
                }
            }
        }
    }
}

}  // namespace thicket
