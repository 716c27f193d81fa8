// Catmull-Clark limit tessellation through OpenSubdiv: Far::TopologyRefiner for uniform
// refinement, Far::PrimvarRefiner for interpolation and limit projection, Bfr::Surface for
// exact evaluation anywhere on a cage face (references and error measurement).
#include "thicket/prims/subdivision.h"

#include "thicket/core/hash.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "thicket/bvh/bvh.h"
#include "thicket/core/error.h"
#include "thicket/prims/triangles.h"

namespace thicket {
namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
namespace Bfr = OpenSubdiv::Bfr;

/// A vertex primvar in double, in the form PrimvarRefiner interpolates.
struct Point {
    double x = 0, y = 0, z = 0;
    void Clear(void* = nullptr) { x = y = z = 0; }
    void AddWithWeight(const Point& p, double w) { x += w * p.x, y += w * p.y, z += w * p.z; }
};
Point operator-(Point a, Point b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Point operator+(Point a, Point b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Point operator*(Point a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double length(Point a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }
Point cross(Point a, Point b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(Point a, Point b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 to_vec3(Point a) { return {float(a.x), float(a.y), float(a.z)}; }

/// The cage's topology as an unrefined refiner (Catmull-Clark, boundary edges and corners
/// interpolated). The cage must have been validated.
std::unique_ptr<Far::TopologyRefiner> make_refiner(const ControlMesh& cage) {
    std::vector<int> sizes(cage.face_sizes.begin(), cage.face_sizes.end());
    std::vector<int> indices(cage.indices.begin(), cage.indices.end());
    Far::TopologyDescriptor desc;
    desc.numVertices = int(cage.positions.size());
    desc.numFaces = int(sizes.size());
    desc.numVertsPerFace = sizes.data();
    desc.vertIndicesPerFace = indices.data();
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
    if (!refiner) throw Error("subdivision: OpenSubdiv rejected the control mesh topology");
    return refiner;
}

void check_level(int level, int lowest) {
    if (level < lowest || level > kMaxSubdivisionLevel)
        throw Error("subdivision: level " + std::to_string(level) + " out of range [" + std::to_string(lowest) + ", " +
                    std::to_string(kMaxSubdivisionLevel) + "]");
}

/// Quads at level >= 1 (every Catmull-Clark face is a quad after one step): 4^level per quad,
/// 4^(level-1) * n per n-gon.
size_t faces_at_level(const ControlMesh& cage, int level) {
    size_t n = 0;
    for (uint32_t s : cage.face_sizes) n += level == 0 ? 1 : (s == 4 ? size_t(1) << (2 * level) : size_t(s) << (2 * (level - 1)));
    return n;
}

/// The refined vertices of the last level moved to the limit, with limit tangents.
struct Refined {
    std::unique_ptr<Far::TopologyRefiner> refiner;
    std::vector<Point> limit, du, dv;  ///< per vertex of the last level
};

Refined refine_to_limit(const ControlMesh& cage, int level) {
    Refined r;
    r.refiner = make_refiner(cage);
    if (level > 0) {
        Far::TopologyRefiner::UniformOptions options(level);
        options.fullTopologyInLastLevel = true;  // Limit() needs it
        r.refiner->RefineUniform(options);
    }
    std::vector<Point> verts(r.refiner->GetNumVerticesTotal());
    for (size_t i = 0; i < cage.positions.size(); ++i)
        verts[i] = {cage.positions[i].x, cage.positions[i].y, cage.positions[i].z};
    Far::PrimvarRefinerReal<double> primvars(*r.refiner);
    Point* src = verts.data();
    for (int l = 1; l <= level; ++l) {
        Point* dst = src + r.refiner->GetLevel(l - 1).GetNumVertices();
        primvars.Interpolate(l, src, dst);
        src = dst;
    }
    const int n = r.refiner->GetLevel(level).GetNumVertices();
    r.limit.resize(n), r.du.resize(n), r.dv.resize(n);
    primvars.Limit(src, r.limit, r.du, r.dv);
    return r;
}

}  // namespace

LimitTessellation tessellate_limit(const ControlMesh& cage, int level) {
    check_level(level, 0);
    validate_control_mesh(cage);
    const size_t faces = faces_at_level(cage, level);
    if (faces * 2 > kMaxSubdivisionTriangles)
        throw Error("subdivision: level " + std::to_string(level) + " would make " + std::to_string(faces * 2) +
                    " triangles (at most " + std::to_string(kMaxSubdivisionTriangles) + ")");
    const Refined r = refine_to_limit(cage, level);
    const Far::TopologyLevel& last = r.refiner->GetLevel(level);

    LimitTessellation out;
    out.mesh.positions.reserve(r.limit.size());
    for (const Point& p : r.limit) out.mesh.positions.push_back(to_vec3(p));
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        const Far::ConstIndexArray fv = last.GetFaceVertices(f);
        if (fv.size() == 4) {
            // The shorter diagonal: the two triangles then follow the surface more closely.
            const bool diag02 = length(r.limit[fv[0]] - r.limit[fv[2]]) <= length(r.limit[fv[1]] - r.limit[fv[3]]);
            const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}}, alt[2][3] = {{0, 1, 3}, {1, 2, 3}};
            for (const auto& t : diag02 ? tri : alt)
                for (int k : t) out.mesh.indices.push_back(uint32_t(fv[k]));
        } else {
            for (int k = 2; k < fv.size(); ++k)
                for (int c : {0, k - 1, k}) out.mesh.indices.push_back(uint32_t(fv[c]));
        }
    }

    // Limit normals, oriented like the cage's faces (the area-weighted triangle normals around
    // the vertex), which also stand in where the limit tangents are degenerate.
    std::vector<Point> around(r.limit.size());
    for (size_t t = 0; t + 2 < out.mesh.indices.size(); t += 3) {
        const uint32_t a = out.mesh.indices[t], b = out.mesh.indices[t + 1], c = out.mesh.indices[t + 2];
        const Point n = cross(r.limit[b] - r.limit[a], r.limit[c] - r.limit[a]);
        for (uint32_t v : {a, b, c}) around[v] = around[v] + n;
    }
    out.normals.resize(r.limit.size());
    for (size_t v = 0; v < r.limit.size(); ++v) {
        Point n = cross(r.du[v], r.dv[v]);
        const double scale = length(r.du[v]) * length(r.dv[v]);
        if (!(length(n) > 1e-12 * scale)) n = around[v];
        else if (dot(n, around[v]) < 0) n = n * -1.0;
        const double len = length(n);
        out.normals[v] = len > 0 ? to_vec3(n * (1.0 / len)) : Vec3(0.0f, 0.0f, 1.0f);
    }
    return out;
}

std::vector<Vec3> limit_positions(const ControlMesh& cage) {
    validate_control_mesh(cage);
    const Refined r = refine_to_limit(cage, 0);
    std::vector<Vec3> out;
    for (const Point& p : r.limit) out.push_back(to_vec3(p));
    return out;
}

std::vector<LimitSample> sample_limit_surface(const ControlMesh& cage, int rate) {
    if (rate < 1 || rate > 1024) throw Error("subdivision: sample rate " + std::to_string(rate) + " out of range [1, 1024]");
    validate_control_mesh(cage);
    const std::unique_ptr<Far::TopologyRefiner> refiner = make_refiner(cage);
    // Bfr represents the neighbourhood of an extraordinary vertex by refinement up to the
    // "smooth approximation level" and a Gregory patch inside the last ring; level 8 (the
    // default is 2) shrinks that approximated region to 1/256 of the face around the vertex.
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(8);
    Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
    std::vector<double> mesh_points;
    for (const Vec3& p : cage.positions) mesh_points.insert(mesh_points.end(), {p.x, p.y, p.z});

    std::vector<LimitSample> out;
    Bfr::Surface<double> surface;
    std::vector<double> patch_points, coords;
    for (int f = 0; f < int(cage.face_count()); ++f) {
        if (!factory.InitVertexSurface(f, &surface)) continue;  // no limit surface (a hole)
        patch_points.resize(size_t(surface.GetNumPatchPoints()) * 3);
        surface.PreparePatchPoints(mesh_points.data(), 3, patch_points.data(), 3);
        Bfr::Tessellation tess(surface.GetParameterization(), rate);
        coords.resize(size_t(tess.GetNumCoords()) * 2);
        tess.GetCoords(coords.data());
        for (int i = 0; i < tess.GetNumCoords(); ++i) {
            double p[3], du[3], dv[3];
            surface.Evaluate(&coords[2 * i], patch_points.data(), 3, p, du, dv);
            const Point n = cross(Point{du[0], du[1], du[2]}, Point{dv[0], dv[1], dv[2]});
            const double len = length(n);
            out.push_back({{float(p[0]), float(p[1]), float(p[2])},
                           len > 0 ? to_vec3(n * (1.0 / len)) : Vec3(0.0f),
                           uint32_t(f), float(coords[2 * i]), float(coords[2 * i + 1])});
        }
    }
    return out;
}

TessellationError tessellation_error(const ControlMesh& cage, int level) {
    check_level(level, 1);
    // Checked against the level the measurement refines to.
    if (faces_at_level(cage, level + 1) * 2 > 4 * kMaxSubdivisionTriangles)
        throw Error("subdivision: measuring level " + std::to_string(level) + " needs too many faces");
    validate_control_mesh(cage);
    const Refined r = refine_to_limit(cage, level + 1);
    const Far::TopologyLevel& coarse = r.refiner->GetLevel(level);
    TessellationError e;
    auto deviation = [&](Far::Index a, Far::Index b, Far::Index mid) {
        const double d = length(r.limit[mid] - (r.limit[a] + r.limit[b]) * 0.5);
        e.max_midpoint_deviation = std::max(e.max_midpoint_deviation, d);
    };
    for (int f = 0; f < coarse.GetNumFaces(); ++f) {
        const Far::ConstIndexArray fv = coarse.GetFaceVertices(f), fe = coarse.GetFaceEdges(f);
        Far::Index corner[4];
        for (int k = 0; k < 4; ++k) corner[k] = coarse.GetVertexChildVertex(fv[k]);
        for (int k = 0; k < 4; ++k) deviation(corner[k], corner[(k + 1) % 4], coarse.GetEdgeChildVertex(fe[k]));
        // The quad's centre is the midpoint of both diagonals; either may be the split.
        const Far::Index centre = coarse.GetFaceChildVertex(f);
        deviation(corner[0], corner[2], centre);
        deviation(corner[1], corner[3], centre);
    }
    e.bound = kErrorBoundFactor * e.max_midpoint_deviation;
    return e;
}

// ---- the kernel ------------------------------------------------------------------------------

struct SubdivisionSurface::Impl {
    int level;
    LimitTessellation tess;
    Bvh<Triangles<TriangleTest::Watertight>> bvh;

    Impl(LimitTessellation t, int l)
        : level(l), tess(std::move(t)), bvh(Triangles<TriangleTest::Watertight>(tess.mesh), BvhBuildOptions{}) {}
};

SubdivisionSurface::SubdivisionSurface(const ControlMesh& cage, int level)
    : impl_(std::make_shared<const Impl>(tessellate_limit(cage, level), level)) {}

Aabb SubdivisionSurface::bounds() const { return impl_->bvh.bounds(); }
int SubdivisionSurface::level() const { return impl_->level; }

uint64_t SubdivisionSurface::hash(uint64_t h) const {
    const TriangleMesh& m = impl_->tess.mesh;
    h = fnv1a(&impl_->level, sizeof impl_->level, h);
    h = fnv1a(m.positions.data(), m.positions.size() * sizeof(Vec3), h);
    return fnv1a(m.indices.data(), m.indices.size() * sizeof(uint32_t), h);
}
const LimitTessellation& SubdivisionSurface::tessellation() const { return impl_->tess; }
size_t SubdivisionSurface::triangle_count() const { return impl_->tess.mesh.triangle_count(); }

size_t SubdivisionSurface::bytes() const {
    const LimitTessellation& t = impl_->tess;
    const AccelStats s = impl_->bvh.stats();
    return t.mesh.positions.size() * sizeof(Vec3) + t.mesh.indices.size() * sizeof(uint32_t) +
           t.normals.size() * sizeof(Vec3) + s.primitive_bytes + s.bytes;
}

bool SubdivisionSurface::intersect(const Ray& ray, float tmax, ShapeHit& hit) const {
    Ray r = ray;
    r.tmax = tmax;
    NoCounters none;
    const Hit h = impl_->bvh.closest(r, none);
    if (!h.found()) return false;
    hit = {h.t, h.u, h.v};
    return true;
}

namespace {

/// Closest point of triangle abc to p as barycentric weights (wb, wc) of b and c (Ericson,
/// Real-Time Collision Detection, 5.1.5), and its squared distance.
float closest_on_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c, float& wb, float& wc) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = dot(ab, ap), d2 = dot(ac, ap);
    auto at = [&](float u, float v) {
        wb = u, wc = v;
        const Vec3 q = a + ab * u + ac * v - p;
        return dot(q, q);
    };
    if (d1 <= 0 && d2 <= 0) return at(0, 0);
    const Vec3 bp = p - b;
    const float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return at(1, 0);
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return at(d1 / (d1 - d3), 0);
    const Vec3 cp = p - c;
    const float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return at(0, 1);
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return at(0, d2 / (d2 - d6));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return at(1 - w, w);
    }
    const float denom = va + vb + vc;
    if (!(denom > 0)) return at(0, 0);  // degenerate triangle: its first vertex
    return at(vb / denom, vc / denom);
}

float box_distance2(const BvhNode& n, Vec3 p) {
    float d = 0;
    for (int a = 0; a < 3; ++a) {
        const float e = std::max({n.aabbMin[a] - p[a], 0.0f, p[a] - n.aabbMax[a]});
        d += e * e;
    }
    return d;
}

}  // namespace

Vec3 SubdivisionSurface::normal(Vec3 p, float, float) const {
    const BvhData& bvh = impl_->bvh.data();
    const TriangleMesh& mesh = impl_->tess.mesh;
    float best = kInfinity, best_b = 0, best_c = 0;
    uint32_t best_tri = 0;
    if (bvh.nodes_used) {
        uint32_t stack[kTraversalStackSize];
        int top = 0;
        stack[top++] = 0;
        while (top) {
            const BvhNode& node = bvh.nodes[stack[--top]];
            if (box_distance2(node, p) > best) continue;
            if (node.is_leaf()) {
                for (uint32_t i = node.leftFirst; i < node.leftFirst + node.count; ++i) {
                    const uint32_t t = bvh.prim_indices[i];
                    float wb, wc;
                    const float d = closest_on_triangle(p, mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2), wb, wc);
                    if (d < best) best = d, best_tri = t, best_b = wb, best_c = wc;
                }
                continue;
            }
            // Nearer child last, so it is popped first.
            const uint32_t l = node.leftFirst, r = l + 1;
            const bool left_nearer = box_distance2(bvh.nodes[l], p) <= box_distance2(bvh.nodes[r], p);
            stack[top++] = left_nearer ? r : l;
            stack[top++] = left_nearer ? l : r;
        }
    }
    if (!(best < kInfinity)) return {0.0f, 0.0f, 1.0f};  // p is NaN: any unit vector
    const auto& n = impl_->tess.normals;
    const uint32_t* idx = &mesh.indices[3 * size_t(best_tri)];
    const Vec3 s = n[idx[0]] * (1 - best_b - best_c) + n[idx[1]] * best_b + n[idx[2]] * best_c;
    const float len = length(s);
    if (len > 1e-6f) return s / len;
    // Opposite vertex normals cancel (a fold of the tessellation): the triangle's own normal.
    const Vec3 g = cross(mesh.vertex(best_tri, 1) - mesh.vertex(best_tri, 0), mesh.vertex(best_tri, 2) - mesh.vertex(best_tri, 0));
    const float gl = length(g);
    return gl > 0 ? g / gl : Vec3(0.0f, 0.0f, 1.0f);
}

}  // namespace thicket
