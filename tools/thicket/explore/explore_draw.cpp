// Each structure's drawing, read from its data: the walkers below take the built arrays (one
// per structure) and keep what lies at the asked depth; draw_structure finds which structure an
// Accel is by the primitive sets the registry builds them over (accel/dispatch.h).
#include "explore_draw.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "explore_as.h"
#include "thicket/bih/bih.h"
#include "thicket/bsp/bsp.h"
#include "thicket/grid/grid.h"
#include "thicket/grid/grid2.h"
#include "thicket/kdtree/kdtree.h"
#include "thicket/obb/obb.h"
#include "thicket/octree/octree.h"
#include "thicket/prims/mixed.h"
#include "thicket/prims/triangles.h"
#include "thicket/tetra/tetra.h"

namespace thicket::explore {

namespace {

using Shape = DrawnElement::Shape;

DrawnElement box_element(uint32_t id, const Aabb& box, bool leaf, uint32_t prims) {
    DrawnElement e;
    e.shape = Shape::Box;
    e.id = id;
    e.box = box;
    e.leaf = leaf;
    e.prims = prims;
    return e;
}

// ---- convex polygons on a plane, clipped by half-spaces (BSP cells are not boxes) ----------

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

// ---- the walkers: one per structure, each keeps what lies at `depth` -----------------------

/// kD-tree: an interior node is its split plane clipped to its cell (a rectangle); a non-empty
/// leaf is its cell. Empty leaves (the SAH's cut-off empty space) are not drawn.
Drawing draw_kdtree(const KdTreeData& kd, uint32_t depth) {
    Drawing d{"planes and leaf cells", "levels of the tree: the planes of the nodes at this depth, "
                                       "and the non-empty leaves that end here", 0, {}};
    if (kd.nodes.empty()) return d;
    struct Item {
        uint32_t node, depth;
        Aabb cell;
    };
    std::vector<Item> stack{{0, 0, kd.bounds}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const KdNode& n = kd.nodes[it.node];
        if (n.is_leaf()) {
            if (n.count() == 0) continue;
            d.max_depth = std::max(d.max_depth, it.depth);
            if (it.depth == depth) d.elements.push_back(box_element(it.node, it.cell, true, n.count()));
            continue;
        }
        d.max_depth = std::max(d.max_depth, it.depth);
        const int a = n.axis(), u = (a + 1) % 3, v = (a + 2) % 3;
        const float s = n.split();
        if (it.depth == depth) {
            DrawnElement e;
            e.shape = Shape::Plane;
            e.id = it.node;
            e.box = it.cell;
            for (const auto& [hu, hv] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
                Vec3 p;
                p[a] = s;
                p[u] = hu ? it.cell.max[u] : it.cell.min[u];
                p[v] = hv ? it.cell.max[v] : it.cell.min[v];
                e.points.push_back(p);
            }
            d.elements.push_back(std::move(e));
        }
        Aabb below = it.cell, above = it.cell;
        below.max[a] = s;
        above.min[a] = s;
        stack.push_back({n.above(), it.depth + 1, above});
        stack.push_back({it.node + 1, it.depth + 1, below});
    }
    return d;
}

/// BSP: an interior node is its plane clipped to its cell, the root box cut by every ancestor's
/// plane on the side the node lies (back: dot(n, p) <= offset, front: >=).
Drawing draw_bsp(const BspData& bsp, uint32_t depth) {
    Drawing d{"planes", "levels of the tree: the planes of the nodes at this depth, each clipped to its "
                        "cell (the root box cut by the planes above it)", 0, {}};
    if (bsp.nodes.empty()) return d;
    std::vector<HalfSpace> path;  // the half-spaces of the current node's ancestors
    // Recursion is bounded: validated trees are at most kBspMaxDepth deep.
    auto walk = [&](auto& self, uint32_t node, uint32_t level) -> void {
        const BspNode& n = bsp.nodes[node];
        if (n.is_leaf()) return;
        d.max_depth = std::max(d.max_depth, level);
        if (level == depth) {
            DrawnElement e;
            e.shape = Shape::Plane;
            e.id = node;
            e.points = plane_in_cell(n.plane.normal, n.plane.offset, bsp.bounds, path);
            if (e.points.size() >= 3) d.elements.push_back(std::move(e));
        }
        const P3 nn{n.plane.normal.x, n.plane.normal.y, n.plane.normal.z};
        path.push_back({nn, double(n.plane.offset)});
        self(self, n.index, level + 1);
        path.back() = {{-nn[0], -nn[1], -nn[2]}, -double(n.plane.offset)};
        self(self, n.index + 1, level + 1);
        path.pop_back();
    };
    walk(walk, 0, 0);
    return d;
}

/// Two-level grid: depth 0 the non-empty top cells, depth 1 the non-empty cells of their sub-grids.
Drawing draw_grid2(const Grid2Data& g, uint32_t depth) {
    Drawing d{"cells", "0: the top grid's non-empty cells; 1: the non-empty cells of their sub-grids", 0, {}};
    const GridFrame& f = g.frame;
    if (g.top.empty()) return d;
    for (uint32_t z = 0; z < f.res[2]; ++z)
        for (uint32_t y = 0; y < f.res[1]; ++y)
            for (uint32_t x = 0; x < f.res[0]; ++x) {
                const uint32_t t = f.index(x, y, z);
                const TopCell& tc = g.top[t];
                if (tc.empty()) continue;
                const uint32_t cell[3] = {x, y, z};
                const GridFrame sub = g.sub_frame(cell, tc);
                uint32_t refs = 0;
                for (uint32_t k = 0; k < sub.cells(); ++k) refs += g.leaves.count(tc.first_leaf + k);
                if (refs == 0) continue;
                if (depth == 0) d.elements.push_back(box_element(t, f.cell_box(x, y, z), false, refs));
                for (uint32_t sz = 0; sz < sub.res[2]; ++sz)
                    for (uint32_t sy = 0; sy < sub.res[1]; ++sy)
                        for (uint32_t sx = 0; sx < sub.res[0]; ++sx) {
                            const uint32_t l = tc.first_leaf + sub.index(sx, sy, sz), n = g.leaves.count(l);
                            if (n == 0) continue;
                            d.max_depth = 1;
                            if (depth == 1) d.elements.push_back(box_element(l, sub.cell_box(sx, sy, sz), true, n));
                        }
            }
    return d;
}

/// Octree: every inner cell and every non-empty leaf cell at the depth.
Drawing draw_octree(const OctreeData& o, uint32_t depth) {
    Drawing d{"cells", "levels of the tree: its inner cells and non-empty leaf cells at this depth", 0, {}};
    if (o.nodes.empty()) return d;
    struct Item {
        uint32_t node, depth;
        Aabb box;
    };
    std::vector<Item> stack{{0, 0, o.root}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const OctreeNode& n = o.nodes[it.node];
        if (n.is_leaf() && n.count == 0) continue;
        d.max_depth = std::max(d.max_depth, it.depth);
        if (it.depth == depth) d.elements.push_back(box_element(it.node, it.box, n.is_leaf(), n.is_leaf() ? n.count : 0));
        if (n.is_leaf()) continue;
        for (int c = 7; c >= 0; --c) stack.push_back({n.index + uint32_t(c), it.depth + 1, octree_child_box(it.box, c)});
    }
    return d;
}

/// BIH: each node's implicit box, the root box cut by its ancestors' clip planes. A child whose
/// interval is empty (the -inf/+inf planes of an empty side) has no box and is not drawn.
Drawing draw_bih(const BihData& b, uint32_t depth) {
    Drawing d{"boxes", "levels of the tree: each node's box, the root box cut by the intervals above it", 0, {}};
    if (b.nodes.empty()) return d;
    struct Item {
        uint32_t node, depth;
        Aabb box;
    };
    std::vector<Item> stack{{0, 0, b.bounds}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        if (it.box.empty()) continue;
        const BihNode& n = b.nodes[it.node];
        d.max_depth = std::max(d.max_depth, it.depth);
        if (it.depth == depth) d.elements.push_back(box_element(it.node, it.box, n.is_leaf(), n.is_leaf() ? n.count() : 0));
        if (n.is_leaf()) continue;
        const int a = n.axis();
        Aabb left = it.box, right = it.box;
        left.max[a] = std::min(left.max[a], n.left_max());
        right.min[a] = std::max(right.min[a], n.right_min());
        stack.push_back({n.index() + 1, it.depth + 1, right});
        stack.push_back({n.index(), it.depth + 1, left});
    }
    return d;
}

/// OBB tree: each node's oriented box (centre and three half-axes).
Drawing draw_obb(const ObbData& o, uint32_t depth) {
    Drawing d{"oriented boxes", "levels of the tree: the oriented boxes of the nodes at this depth", 0, {}};
    if (o.nodes.empty()) return d;
    struct Item {
        uint32_t node, depth;
    };
    std::vector<Item> stack{{0, 0}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        const ObbNode& n = o.nodes[it.node];
        d.max_depth = std::max(d.max_depth, it.depth);
        if (it.depth == depth) {
            DrawnElement e;
            e.shape = Shape::Oriented;
            e.id = it.node;
            e.leaf = n.is_leaf();
            e.prims = n.count;
            e.points = {n.center, n.axis[0] * n.half.x, n.axis[1] * n.half.y, n.axis[2] * n.half.z};
            d.elements.push_back(std::move(e));
        }
        if (n.is_leaf()) continue;
        stack.push_back({n.leftFirst + 1, it.depth + 1});
        stack.push_back({n.leftFirst, it.depth + 1});
    }
    return d;
}

/// Tetrahedral mesh: depth k is the tetrahedra k steps (across faces) from the nearest one with
/// a face on the scene's surface, so depth 0 hugs the mesh and deeper levels fill the empty space
/// a ray walks through. A mesh with no surface face (every triangle refused) is all depth 0.
Drawing draw_tetra(const TetraMesh& m, uint32_t depth) {
    Drawing d{"tetrahedra", "steps (across faces) from the nearest tetrahedron touching the scene's surface", 0, {}};
    const size_t n = m.tet_count();
    if (n == 0) return d;
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
        d.max_depth = std::max(d.max_depth, level[t]);
        if (level[t] != depth) continue;
        DrawnElement e;
        e.shape = Shape::Tetra;
        e.id = t;
        for (int k = 0; k < 4; ++k) {
            const Vec3d& p = m.points[m.tets[4 * t + k]];
            e.points.push_back({float(p.x), float(p.y), float(p.z)});
        }
        d.elements.push_back(std::move(e));
    }
    return d;
}

/// The nodes a structure names through Accel::for_each_node (bvh, grid), as boxes.
std::optional<Drawing> draw_nodes(const Accel& accel, uint32_t depth, const char* kind, const char* means) {
    Drawing d{kind, means, 0, {}};
    const bool draws = accel.for_each_node([&](const NodeBox& n) {
        d.max_depth = std::max(d.max_depth, n.depth);
        if (n.depth == depth) d.elements.push_back(box_element(n.id, n.box, n.leaf, n.prims));
    });
    if (!draws) return std::nullopt;
    return d;
}

}  // namespace

std::optional<Drawing> draw_structure(const Accel& accel, uint32_t depth) {
    std::optional<Drawing> d;
    const auto take = [&](Drawing drawing) { d = std::move(drawing); };
    if (as<KdTree>(accel, [&](const auto& s) { take(draw_kdtree(s.data(), depth)); })) return d;
    if (as<Bsp>(accel, [&](const auto& s) { take(draw_bsp(s.data(), depth)); })) return d;
    if (as<TwoLevelGrid>(accel, [&](const auto& s) { take(draw_grid2(s.data(), depth)); })) return d;
    if (as<Octree>(accel, [&](const auto& s) { take(draw_octree(s.data(), depth)); })) return d;
    if (as<Bih>(accel, [&](const auto& s) { take(draw_bih(s.data(), depth)); })) return d;
    if (as<Obb>(accel, [&](const auto& s) { take(draw_obb(s.data(), depth)); })) return d;
    if (as<Tetra>(accel, [&](const auto& s) { take(draw_tetra(s.data().mesh, depth)); })) return d;
    if (as<Grid>(accel, [](const auto&) {}))
        return draw_nodes(accel, depth, "cells", "one level: the grid's non-empty cells");
    return draw_nodes(accel, depth, "boxes", "levels of the tree: the boxes of the nodes at this depth");
}

bool draws_itself(const Accel& accel) {
    const auto any = [](const auto&) {};
    return as<KdTree>(accel, any) || as<Bsp>(accel, any) || as<TwoLevelGrid>(accel, any) || as<Octree>(accel, any) ||
           as<Bih>(accel, any) || as<Obb>(accel, any) || as<Tetra>(accel, any) ||
           accel.for_each_node([](const NodeBox&) {});
}

}  // namespace thicket::explore
