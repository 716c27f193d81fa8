// Building the tetrahedralization: the scene's triangles cleaned (welded vertices; degenerate
// and duplicate triangles set aside), handed to TetGen with the 8 corners of a box around them;
// what TetGen refuses is found with its own self-intersection detection (-d) and set aside
// too, and the rest retried once. Whatever is set aside, and every shape, goes to a fallback
// BVH. Then the mesh is checked (every meshed triangle covered by its constrained faces) and
// indexed for the walk.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_map>

#include "tetra/tetgen_run.h"
#include "thicket/bvh/build.h"
#include "thicket/core/error.h"
#include "thicket/geometry/weld.h"
#include "thicket/tetra/build.h"
#include "thicket/tetra/walk.h"

namespace thicket {

namespace {

using tetra_detail::TetgenInput;
using tetra_detail::TetgenResult;

// PointBitsHash (geometry/weld.h) hashes any three 32-bit words: a vertex's coordinate bits, a
// face's sorted vertex ids.

/// The scene's triangles as TetGen's input: welded vertices (box corners first), triangles
/// that are neither degenerate nor repeats; the others are appended to `fallback`.
struct Cleaned {
    TetgenInput in;
    std::vector<uint32_t> prims;  ///< scene id of each triangle of `in`
};

Cleaned clean(const TetraInput& input, std::vector<uint32_t>& fallback, Vec3d& lo, Vec3d& hi) {
    Cleaned c;
    std::unordered_map<std::array<uint32_t, 3>, int, PointBitsHash> ids;
    std::unordered_map<std::array<uint32_t, 3>, int, PointBitsHash> seen;  // sorted vertex ids
    std::vector<Vec3> verts;
    Aabb box;
    for (uint32_t i = 0; i < input.count; ++i) {
        if (!input.is_triangle(i)) {
            fallback.push_back(i);
            continue;
        }
        const std::array<Vec3, 3> t = input.triangle(i);
        std::array<uint32_t, 3> tri;
        bool finite = true;
        for (int k = 0; k < 3; ++k) {
            finite = finite && std::isfinite(t[k].x) && std::isfinite(t[k].y) && std::isfinite(t[k].z);
            const auto [it, added] = ids.try_emplace(point_bits(t[k]), int(verts.size()));
            if (added) verts.push_back(t[k]);
            tri[k] = uint32_t(it->second);
        }
        // Degenerate: repeated vertices, or an area TetGen's tolerance would take for none.
        const Vec3d a = Vec3d(t[0]), e1 = Vec3d(t[1]) - a, e2 = Vec3d(t[2]) - a, e3 = Vec3d(t[2]) - Vec3d(t[1]);
        const Vec3d n = cross(e1, e2);
        const double longest = std::max({dot(e1, e1), dot(e2, e2), dot(e3, e3)});
        std::array<uint32_t, 3> key = tri;
        std::sort(key.begin(), key.end());
        if (!finite || key[0] == key[1] || key[1] == key[2] || !(dot(n, n) > 1e-12 * longest * longest) ||
            !seen.try_emplace(key, 0).second) {
            fallback.push_back(i);
            continue;
        }
        for (int k = 0; k < 3; ++k) c.in.triangles.push_back(int(tri[k]) + 8);
        c.in.markers.push_back(int(c.prims.size()) + 1);
        c.prims.push_back(i);
        for (const Vec3& v : t) box.grow(v);
    }
    // The box: the meshed triangles' bounds grown by a tenth of their largest extent.
    const float grow = std::max(max_component(box.extent()) * 0.1f, 1e-30f);
    lo = Vec3d(box.min - Vec3(grow));
    hi = Vec3d(box.max + Vec3(grow));
    for (int corner = 0; corner < 8; ++corner) {
        c.in.points.push_back(corner & 1 ? hi.x : lo.x);
        c.in.points.push_back(corner & 2 ? hi.y : lo.y);
        c.in.points.push_back(corner & 4 ? hi.z : lo.z);
    }
    for (const Vec3& v : verts) {
        c.in.points.push_back(v.x);
        c.in.points.push_back(v.y);
        c.in.points.push_back(v.z);
    }
    return c;
}

/// Keeps only the triangles of `c` whose marker is not in `drop` (renumbering markers), moving
/// the dropped ones' scene ids to `fallback`.
void drop_triangles(Cleaned& c, const std::vector<int>& drop, std::vector<uint32_t>& fallback) {
    std::vector<uint8_t> gone(c.prims.size(), 0);
    for (int m : drop)
        if (m >= 1 && size_t(m) <= c.prims.size()) gone[size_t(m) - 1] = 1;
    Cleaned kept;
    kept.in.points = std::move(c.in.points);
    for (size_t t = 0; t < c.prims.size(); ++t) {
        if (gone[t]) {
            fallback.push_back(c.prims[t]);
            continue;
        }
        for (int k = 0; k < 3; ++k) kept.in.triangles.push_back(c.in.triangles[3 * t + k]);
        kept.in.markers.push_back(int(kept.prims.size()) + 1);
        kept.prims.push_back(c.prims[t]);
    }
    c = std::move(kept);
}

/// Adds one sentence to the report's outcome.
void note(TetraReport& r, const std::string& text) { r.outcome += (r.outcome.empty() ? "" : "; ") + text; }

/// The mesh from TetGen's output: tetrahedra made positive, constrained faces' triangles per
/// vertex, triangles whose faces do not cover them moved to `fallback`.
void assemble(const TetgenResult& r, const Cleaned& c, const TetraInput& input, TetraData& data) {
    TetraMesh& m = data.mesh;
    const auto& o = r.out;
    m.points.resize(o.points.size() / 3);
    for (size_t i = 0; i < m.points.size(); ++i) m.points[i] = {o.points[3 * i], o.points[3 * i + 1], o.points[3 * i + 2]};
    const size_t tets = o.tets.size() / 4;
    m.tets.assign(o.tets.begin(), o.tets.end());
    m.neighbors.resize(tets * 4);
    for (size_t i = 0; i < tets * 4; ++i) m.neighbors[i] = o.neighbors[i] < 0 ? kNoTet : uint32_t(o.neighbors[i]);
    // Orientation: TetGen's tetrahedra all turn the same way; make it the positive one.
    size_t negative = 0;
    for (size_t t = 0; t < tets; ++t) {
        const uint32_t* v = &m.tets[4 * t];
        negative += tetra_detail::orient(m.points[v[0]], m.points[v[1]], m.points[v[2]], m.points[v[3]]) < 0;
    }
    if (negative * 2 > tets)
        for (size_t t = 0; t < tets; ++t) {
            std::swap(m.tets[4 * t], m.tets[4 * t + 1]);
            std::swap(m.neighbors[4 * t], m.neighbors[4 * t + 1]);
        }
    // Constrained faces: their triangle at each of their vertices, and the area they cover.
    std::vector<double> covered(c.prims.size(), 0.0);
    std::vector<std::pair<uint32_t, uint32_t>> at;  // (vertex, triangle of `c`)
    for (size_t f = 0; f < o.face_markers.size(); ++f) {
        const int marker = o.face_markers[f];
        if (marker < 1 || size_t(marker) > c.prims.size()) continue;
        const int* v = &o.faces[3 * f];
        const Vec3d n = cross(m.points[v[1]] - m.points[v[0]], m.points[v[2]] - m.points[v[0]]);
        covered[size_t(marker) - 1] += 0.5 * std::sqrt(dot(n, n));
        for (int k = 0; k < 3; ++k) at.push_back({uint32_t(v[k]), uint32_t(marker - 1)});
    }
    std::vector<uint8_t> meshed(c.prims.size(), 0);
    for (size_t t = 0; t < c.prims.size(); ++t) {
        const std::array<Vec3, 3> v = input.triangle(c.prims[t]);
        const Vec3d n = cross(Vec3d(v[1]) - Vec3d(v[0]), Vec3d(v[2]) - Vec3d(v[0]));
        const double area = 0.5 * std::sqrt(dot(n, n));
        meshed[t] = std::fabs(covered[t] - area) <= 1e-6 * area;
        if (!meshed[t]) data.fallback.push_back(c.prims[t]);
    }
    const size_t uncovered = size_t(std::count(meshed.begin(), meshed.end(), 0));
    if (uncovered > 0)
        note(data.report, std::to_string(uncovered) + " triangle(s) not covered by their constrained faces set aside");
    // Each tetrahedron face's triangle, looked up by the face's sorted vertex ids.
    std::unordered_map<std::array<uint32_t, 3>, uint32_t, PointBitsHash> face_of;
    for (size_t f = 0; f < o.face_markers.size(); ++f) {
        const int marker = o.face_markers[f];
        if (marker < 1 || size_t(marker) > c.prims.size() || !meshed[size_t(marker) - 1]) continue;
        std::array<uint32_t, 3> key{uint32_t(o.faces[3 * f]), uint32_t(o.faces[3 * f + 1]), uint32_t(o.faces[3 * f + 2])};
        std::sort(key.begin(), key.end());
        face_of[key] = c.prims[size_t(marker) - 1];
    }
    m.face_tris.assign(tets * 4, kNoTet);
    for (size_t t = 0; t < tets && !face_of.empty(); ++t)
        for (int k = 0; k < 4; ++k) {
            std::array<uint32_t, 3> key;
            int j = 0;
            for (int i = 0; i < 4; ++i)
                if (i != k) key[j++] = m.tets[4 * t + i];
            std::sort(key.begin(), key.end());
            const auto it = face_of.find(key);
            if (it != face_of.end()) m.face_tris[4 * t + k] = it->second;
        }
    std::sort(at.begin(), at.end());
    at.erase(std::unique(at.begin(), at.end()), at.end());
    m.vertex_offsets.assign(m.points.size() + 1, 0);
    for (const auto& [v, t] : at)
        if (meshed[t]) {
            ++m.vertex_offsets[v + 1];
            m.vertex_tris.push_back(c.prims[t]);
        }
    for (size_t v = 0; v < m.points.size(); ++v) m.vertex_offsets[v + 1] += m.vertex_offsets[v];
    data.report.meshed_triangles = uint32_t(std::count(meshed.begin(), meshed.end(), 1));
    data.report.steiner_points = uint32_t(m.points.size() - c.in.points.size() / 3);
}

/// The start grid: per cell, the tetrahedron holding its centre.
void index_starts(TetraMesh& m) {
    m.grid_res = uint32_t(std::clamp(std::cbrt(double(m.tet_count()) / 8.0), 1.0, 32.0));
    const uint32_t r = m.grid_res;
    m.grid_start.assign(size_t(r) * r * r, 0);
    uint32_t t = 0;
    for (uint32_t z = 0; z < r; ++z)
        for (uint32_t y = 0; y < r; ++y)
            for (uint32_t x = 0; x < r; ++x) {
                const Vec3d p{m.box_min.x + (m.box_max.x - m.box_min.x) * (x + 0.5) / r,
                           m.box_min.y + (m.box_max.y - m.box_min.y) * (y + 0.5) / r,
                           m.box_min.z + (m.box_max.z - m.box_min.z) * (z + 0.5) / r};
                t = tetra_detail::locate(m, p, t, [] {});
                m.grid_start[(size_t(z) * r + y) * r + x] = t;
            }
}

}  // namespace

TetraData build_tetra(const TetraInput& input, const TetraBuildOptions& options) {
    TetraData data;
    data.report.input_triangles = 0;
    for (uint32_t i = 0; i < input.count; ++i) data.report.input_triangles += input.is_triangle(i);
    Vec3d lo, hi;
    Cleaned c = clean(input, data.fallback, lo, hi);
    if (c.prims.size() > options.max_triangles) {
        note(data.report, std::to_string(c.prims.size()) + " triangles to mesh, over max-triangles=" +
                              std::to_string(options.max_triangles) + ": all in the fallback bvh");
        for (uint32_t p : c.prims) data.fallback.push_back(p);
        c.prims.clear();
    } else if (data.fallback.size() > 0) {
        note(data.report, std::to_string(data.fallback.size()) + " primitive(s) not triangles, degenerate or repeated");
    }
    if (!c.prims.empty()) {
        const std::string switches = std::string("pMQnz") + (options.preserve_surface ? "Y" : "");
        TetgenResult r = tetra_detail::run_tetgen(c.in, switches, options.time_limit_s, options.memory_limit_mb);
        data.report.tetgen_runs = 1;
        data.report.tetgen_ms = r.ms;
        if (!r.ok && r.failure.find("time limit") == std::string::npos) {
            // Find what TetGen refuses with its own detection, set it aside, and try once more.
            const std::string first = r.failure;
            TetgenResult detect = tetra_detail::run_tetgen(c.in, "pdMQz", options.time_limit_s, options.memory_limit_mb);
            data.report.tetgen_runs = 2;
            data.report.tetgen_ms += detect.ms;
            if (detect.ok && !detect.out.face_markers.empty()) {
                const size_t before = data.fallback.size();
                drop_triangles(c, detect.out.face_markers, data.fallback);
                note(data.report, first + ": " + std::to_string(data.fallback.size() - before) +
                                      " intersecting triangle(s) set aside (TetGen -d)");
                if (!c.prims.empty()) {
                    r = tetra_detail::run_tetgen(c.in, switches, options.time_limit_s, options.memory_limit_mb);
                    data.report.tetgen_runs = 3;
                    data.report.tetgen_ms += r.ms;
                }
            }
        }
        if (r.ok) {
            data.mesh.box_min = lo;
            data.mesh.box_max = hi;
            assemble(r, c, input, data);
            index_starts(data.mesh);
        } else if (!c.prims.empty()) {
            note(data.report, r.failure + ": nothing meshed, all " + std::to_string(c.prims.size()) +
                                  " triangles in the fallback bvh");
            for (uint32_t p : c.prims) data.fallback.push_back(p);
        }
    }
    std::sort(data.fallback.begin(), data.fallback.end());
    data.fallback.erase(std::unique(data.fallback.begin(), data.fallback.end()), data.fallback.end());
    std::vector<Aabb> bounds(data.fallback.size());
    std::vector<Vec3> centroids(data.fallback.size());
    for (size_t i = 0; i < data.fallback.size(); ++i) {
        bounds[i] = input.bounds(data.fallback[i]);
        centroids[i] = bounds[i].center();
    }
    BvhBuildOptions bo;
    bo.threads = options.threads;
    data.fallback_bvh = build_bvh({bounds, centroids}, bo);
    return data;
}

}  // namespace thicket
