// The tetra structure's load-time proof beyond structure (validate_tetra): what the walk relies
// on for its answers.
//   1. The tetrahedra tile the box once. Every vertex lies in the box; each tetrahedron has four
//      distinct vertices and is positive by the walk's own face planes (each vertex behind the
//      opposite face, up to rounding); every face with a neighbour is that neighbour's face too
//      (same three vertices, the neighbour naming this tetrahedron back), seen from the other
//      side (face_plane's normals opposite), carrying the same triangle; every face without one
//      lies in a face of the box; and the volumes add up to the box's. Positive tetrahedra glued
//      face to face with the open faces on the box's surface cover the box a whole number of
//      times, and the volume says once: every ray walks through the cells its path crosses.
//   2. Every meshed triangle is covered by the faces that carry it. Each such face lies on the
//      triangle (its vertices within a tolerance of the triangle's plane and inside its edges);
//      every edge of those faces is shared by exactly two of them or lies on an edge of the
//      triangle; and at least one face carries it. Such a patch covers the triangle (its border
//      is the triangle's), so a ray through the triangle crosses a face that names it. Each
//      carrying face's vertices list the triangle (the walk's tests near edges rely on it).
//   3. The fallback BVH's boxes contain the fallback primitives (validate_bvh_bounds).
// The start grid needs no proof: any tetrahedron is a valid start of the point location walk.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <unordered_map>
#include <vector>

#include "thicket/bvh/build.h"
#include "thicket/core/error.h"
#include "thicket/tetra/build.h"
#include "tetra/invalid.h"
#include "thicket/tetra/walk.h"

namespace thicket {

namespace {

/// Face k of tetrahedron t: its vertex ids sorted, and whether face_plane() negates the normal
/// of the sorted vertices (the parity face_plane computes).
struct Face {
    std::array<uint32_t, 3> v;
    bool flip;
};
Face face_of(const TetraMesh& m, size_t t, int k) {
    Face f{};
    int j = 0;
    for (int i = 0; i < 4; ++i)
        if (i != k) f.v[size_t(j++)] = m.tets[4 * t + size_t(i)];
    f.flip = (k & 1) != 0;
    if (f.v[0] > f.v[1]) std::swap(f.v[0], f.v[1]), f.flip = !f.flip;
    if (f.v[1] > f.v[2]) std::swap(f.v[1], f.v[2]), f.flip = !f.flip;
    if (f.v[0] > f.v[1]) std::swap(f.v[0], f.v[1]), f.flip = !f.flip;
    return f;
}

struct EdgeHash {
    size_t operator()(uint64_t e) const { return size_t(e * 0x9E3779B97F4A7C15ull); }
};

/// Part 1: the tetrahedra tile the box once.
void prove_tiling(const TetraMesh& m) {
    const size_t tets = m.tet_count();
    for (size_t i = 0; i < m.points.size(); ++i)
        for (int a = 0; a < 3; ++a)
            if (!(m.points[i][a] >= m.box_min[a] && m.points[i][a] <= m.box_max[a]))
                invalid_tetra("vertex " + std::to_string(i) + " lies outside the box");
    double volume = 0;
    for (size_t t = 0; t < tets; ++t) {
        const uint32_t* v = &m.tets[4 * t];
        const std::string at = "tetrahedron " + std::to_string(t);
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j)
                if (v[i] == v[j]) invalid_tetra(at + " repeats vertex " + std::to_string(v[i]));
        // Positive: each vertex behind the opposite face's outward plane. Rounding of the
        // determinant is below 1e-15 of the cube of the longest edge; a sliver TetGen made
        // (positive in exact arithmetic) can come out of double at most that far negative.
        double longest = 0;
        for (int i = 0; i < 4; ++i)
            for (int j = i + 1; j < 4; ++j) longest = std::max(longest, length(m.points[v[i]] - m.points[v[j]]));
        const double slack = 1e-12 * longest * longest * longest;
        for (int k = 0; k < 4; ++k) {
            Vec3d n, a;
            tetra_detail::face_plane(m, uint32_t(t), k, n, a);
            if (!(dot(n, a - m.points[v[k]]) >= -slack)) invalid_tetra(at + " is inverted (vertex " + std::to_string(k) +
                                                                 " in front of its opposite face)");
        }
        volume += tetra_detail::orient(m.points[v[0]], m.points[v[1]], m.points[v[2]], m.points[v[3]]);
        for (int k = 0; k < 4; ++k) {
            const Face f = face_of(m, t, k);
            const uint32_t u = m.neighbors[4 * t + size_t(k)];
            const std::string face = at + " face " + std::to_string(k);
            if (u == kNoTet) {
                // An open face must lie in one of the box's faces: the walk leaves the mesh there.
                bool on_box = false;
                for (int a = 0; a < 3 && !on_box; ++a)
                    for (const double side : {m.box_min[a], m.box_max[a]})
                        on_box = on_box || (m.points[f.v[0]][a] == side && m.points[f.v[1]][a] == side &&
                                            m.points[f.v[2]][a] == side);
                if (!on_box) invalid_tetra(face + " has no neighbour but is not on the box");
                continue;
            }
            if (u == t) invalid_tetra(face + " is its own neighbour");
            int back = -1;
            for (int j = 0; j < 4; ++j)
                if (m.neighbors[4 * size_t(u) + size_t(j)] == t) back = j;
            if (back < 0) invalid_tetra(face + ": neighbour " + std::to_string(u) + " does not name it back");
            const Face g = face_of(m, u, back);
            if (g.v != f.v) invalid_tetra(face + " and its neighbour " + std::to_string(u) + " do not share the face");
            if (g.flip == f.flip) invalid_tetra(face + " and its neighbour " + std::to_string(u) + " lie on the same side of it");
            if (m.face_tris[4 * t + size_t(k)] != m.face_tris[4 * size_t(u) + size_t(back)])
                invalid_tetra(face + " and its neighbour " + std::to_string(u) + " carry different triangles");
        }
    }
    // The sum of the (rounded) volumes of a once-covered box: exact up to 1e-15 per tetrahedron
    // of the box's bounding cube; a second cover, or a hole, would change it by a tetrahedron.
    const Vec3d e = m.box_max - m.box_min;
    const double box = 6.0 * e.x * e.y * e.z, cube = std::pow(std::max({e.x, e.y, e.z}), 3.0);
    if (!(std::fabs(volume - box) <= 1e-7 * box + 1e-14 * double(tets) * cube))
        invalid_tetra("the tetrahedra's volumes do not add up to the box's (they overlap or leave a hole)");
}

/// Signed distance of p from the line of edge (a, b) of a triangle of normal n, positive
/// inside the triangle.
double inside(const Vec3d& a, const Vec3d& b, const Vec3d& n, const Vec3d& p) {
    const Vec3d edge = b - a;
    return dot(cross(edge, p - a), n) / (length(edge) * length(n));
}

/// Part 2: every meshed triangle covered by the faces that carry it.
void prove_carried(const TetraMesh& m, const TetraInput& input) {
    // Distinct carrying faces (a face is seen from both of its tetrahedra), grouped by triangle.
    std::vector<std::pair<uint32_t, std::array<uint32_t, 3>>> faces;
    for (size_t t = 0; t < m.tet_count(); ++t)
        for (int k = 0; k < 4; ++k) {
            const uint32_t p = m.face_tris[4 * t + size_t(k)];
            if (p != kNoTet) faces.push_back({p, face_of(m, t, k).v});
        }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    // The triangles listed at each vertex, sorted for lookup.
    std::vector<uint32_t> listed = m.vertex_tris;
    for (size_t v = 0; v + 1 < m.vertex_offsets.size(); ++v)
        std::sort(listed.begin() + m.vertex_offsets[v], listed.begin() + m.vertex_offsets[v + 1]);
    std::vector<uint8_t> carried(input.count, 0);
    std::unordered_map<uint64_t, uint32_t, EdgeHash> edges;  // edge (two vertex ids) -> faces of it
    for (size_t begin = 0; begin < faces.size();) {
        const uint32_t p = faces[begin].first;
        size_t end = begin;
        while (end < faces.size() && faces[end].first == p) ++end;
        const std::string tri = "triangle " + std::to_string(p);
        if (!input.is_triangle(p)) invalid_tetra("a face carries primitive " + std::to_string(p) + ", not a triangle");
        carried[p] = 1;
        const std::array<Vec3, 3> c = input.triangle(p);
        const Vec3d a = Vec3d(c[0]), b = Vec3d(c[1]), d = Vec3d(c[2]);
        const Vec3d n = cross(b - a, d - a);
        // Tolerance: TetGen's Steiner points on the triangle are rounded to double (error a few
        // 1e-16 of their coordinates); the builder meshes only triangles taller than 1e-6 of
        // their longest edge, far above it.
        double magnitude = 0;
        for (const Vec3d& q : {a, b, d})
            for (int i = 0; i < 3; ++i) magnitude = std::max(magnitude, std::fabs(q[i]));
        const double tol = 1e-12 * magnitude + 1e-9 * std::max({length(b - a), length(d - a), length(d - b)});
        const Vec3d corners[3] = {a, b, d};
        // Which edges of the triangle (bit e: from corner e to e+1) vertex x lies on.
        auto on_edges = [&](uint32_t x) {
            const Vec3d& q = m.points[x];
            if (!(std::fabs(dot(n, q - a)) <= tol * length(n)))
                invalid_tetra(tri + ": vertex " + std::to_string(x) + " of a face carrying it is off its plane");
            unsigned bits = 0;
            for (int e = 0; e < 3; ++e) {
                const double s = inside(corners[e], corners[(e + 1) % 3], n, q);
                if (!(s >= -tol)) invalid_tetra(tri + ": vertex " + std::to_string(x) + " of a face carrying it is outside it");
                if (s <= tol) bits |= 1u << e;
            }
            return bits;
        };
        edges.clear();
        for (size_t i = begin; i < end; ++i) {
            const auto& f = faces[i].second;
            for (uint32_t x : f) {
                const auto first = listed.begin() + m.vertex_offsets[x], last = listed.begin() + m.vertex_offsets[x + 1];
                if (!std::binary_search(first, last, p))
                    invalid_tetra(tri + " is carried by a face at vertex " + std::to_string(x) + ", which does not list it");
            }
            // The face's vertices are sorted: each edge is keyed smaller id first.
            for (auto [x, y] : {std::pair{f[0], f[1]}, std::pair{f[1], f[2]}, std::pair{f[0], f[2]}})
                ++edges[uint64_t(x) << 32 | y];
        }
        for (const auto& [key, count] : edges) {
            const uint32_t x = uint32_t(key >> 32), y = uint32_t(key);
            if (count == 2) continue;
            if (count == 1 && (on_edges(x) & on_edges(y)) != 0) continue;
            invalid_tetra(tri + ": the faces carrying it leave a gap or overlap at the edge between vertices " +
                    std::to_string(x) + " and " + std::to_string(y));
        }
        for (size_t i = begin; i < end; ++i)
            for (uint32_t x : faces[i].second) on_edges(x);
        begin = end;
    }
    for (uint32_t p : m.vertex_tris)
        if (!carried[p]) invalid_tetra("triangle " + std::to_string(p) + " is meshed but no face carries it");
}

}  // namespace

void validate_tetra_geometry(const TetraData& data, const TetraInput& input) {
    const TetraMesh& m = data.mesh;
    if (m.tet_count() > 0) {
        prove_tiling(m);
        prove_carried(m, input);
    }
    std::vector<Aabb> bounds(data.fallback.size());
    for (size_t i = 0; i < bounds.size(); ++i) bounds[i] = input.bounds(data.fallback[i]);
    validate_bvh_bounds(data.fallback_bvh, bounds);
}

}  // namespace thicket
