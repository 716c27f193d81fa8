// The BSP tree's drawing (bsp/draw.h): BSP cells are not boxes, so each plane is a square larger
// than the root box, clipped by the root box and by every ancestor's half-space in double.
#include "thicket/bsp/draw.h"

#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace thicket {

namespace {

using P3 = std::array<double, 3>;

double dot3(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// A half-space {p : dot(n, p) <= d}.
struct HalfSpace {
    P3 n;
    double d;
};

/// The part of convex `poly` inside `h` (Sutherland-Hodgman against one plane).
std::vector<P3> clip(const std::vector<P3>& poly, const HalfSpace& h) {
    std::vector<P3> out;
    for (size_t i = 0; i < poly.size(); ++i) {
        const P3& a = poly[i];
        const P3& b = poly[(i + 1) % poly.size()];
        const double da = dot3(h.n, a) - h.d, db = dot3(h.n, b) - h.d;
        if (da <= 0) out.push_back(a);
        if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
            const double s = da / (da - db);
            out.push_back({a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2])});
        }
    }
    return out;
}

/// The plane {p : dot(n, p) = offset} (n of unit length) inside `box` and every half-space of
/// `cuts`: a convex polygon, fewer than 3 corners when the plane misses that cell.
std::vector<Vec3> plane_in_cell(const Vec3& n, float offset, const Aabb& box, const std::vector<HalfSpace>& cuts) {
    const P3 nn{n.x, n.y, n.z};
    const Vec3 c = box.center();
    const double lift = double(offset) - dot3(nn, {c.x, c.y, c.z});
    const P3 on{c.x + lift * nn[0], c.y + lift * nn[1], c.z + lift * nn[2]};
    // Two directions spanning the plane; the first is across the normal's smallest component.
    const int small = std::fabs(nn[0]) <= std::fabs(nn[1]) && std::fabs(nn[0]) <= std::fabs(nn[2]) ? 0
                      : std::fabs(nn[1]) <= std::fabs(nn[2])                                          ? 1
                                                                                                       : 2;
    P3 e{0, 0, 0};
    e[size_t(small)] = 1;
    P3 u{nn[1] * e[2] - nn[2] * e[1], nn[2] * e[0] - nn[0] * e[2], nn[0] * e[1] - nn[1] * e[0]};
    const double lu = std::sqrt(dot3(u, u));
    for (double& x : u) x /= lu;
    const P3 v{nn[1] * u[2] - nn[2] * u[1], nn[2] * u[0] - nn[0] * u[2], nn[0] * u[1] - nn[1] * u[0]};
    // A square larger than the box around the plane's point nearest the box's centre.
    const Vec3 ext = box.extent();
    const double r = 2.0 * (double(length(ext)) + std::fabs(lift)) + 1.0;
    std::vector<P3> poly;
    for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
        poly.push_back({on[0] + r * (a * u[0] + b * v[0]), on[1] + r * (a * u[1] + b * v[1]),
                        on[2] + r * (a * u[2] + b * v[2])});
    for (int a = 0; a < 3 && poly.size() >= 3; ++a) {
        P3 axis{0, 0, 0};
        axis[size_t(a)] = 1;
        poly = clip(poly, {axis, double(box.max[a])});
        axis[size_t(a)] = -1;
        if (poly.size() >= 3) poly = clip(poly, {axis, -double(box.min[a])});
    }
    for (const HalfSpace& h : cuts)
        if (poly.size() >= 3) poly = clip(poly, h);
    std::vector<Vec3> out;
    if (poly.size() < 3) return out;
    for (const P3& p : poly) out.push_back({float(p[0]), float(p[1]), float(p[2])});
    return out;
}

}  // namespace

void draw_nodes(const BspData& bsp, const DrawnNodeVisitor& visit) {
    if (bsp.nodes.empty()) return;
    std::vector<HalfSpace> path;  // the half-spaces of the current node's ancestors
    // Recursion is bounded: validated trees are at most kBspMaxDepth deep.
    auto walk = [&](auto& self, uint32_t node, uint32_t level) -> void {
        const BspNode& n = bsp.nodes[node];
        if (n.is_leaf()) return;
        DrawnNode d = drawn_box(node, level, Aabb{}, false, 0);
        d.shape = DrawnNode::Shape::Plane;
        d.points = plane_in_cell(n.plane.normal, n.plane.offset, bsp.bounds, path);
        visit(d);
        const P3 nn{n.plane.normal.x, n.plane.normal.y, n.plane.normal.z};
        path.push_back({nn, double(n.plane.offset)});  // back: dot(n, p) <= offset
        self(self, n.index, level + 1);
        path.back() = {{-nn[0], -nn[1], -nn[2]}, -double(n.plane.offset)};  // front: >=
        self(self, n.index + 1, level + 1);
        path.pop_back();
    };
    walk(walk, 0, 0);
}

DrawingLegend draw_legend(const BspData&) {
    return {"planes", "levels of the tree: the planes of the nodes at this depth, each clipped to its "
                      "cell (the root box cut by the planes above it)"};
}

}  // namespace thicket
