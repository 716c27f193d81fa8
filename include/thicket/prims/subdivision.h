#pragma once
/// Catmull-Clark subdivision surfaces (through OpenSubdiv) as a shape kernel: the control mesh
/// is refined uniformly to a level, every vertex of that level is moved to its exact limit
/// position, the quads are split into triangles, and a private BVH over them answers rays.
/// The tessellation's distance from the limit surface is estimated by tessellation_error().
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"
#include "thicket/prims/control_mesh.h"
#include "thicket/prims/shape.h"
#include "thicket/geometry/mesh.h"

namespace thicket {

inline constexpr int kMaxSubdivisionLevel = 8;
/// Most triangles a tessellation may have (about 1 GiB with its BVH): beyond, Error.
inline constexpr size_t kMaxSubdivisionTriangles = size_t(1) << 24;

/// A tessellation whose vertices lie on the limit surface.
struct LimitTessellation {
    TriangleMesh mesh;         ///< vertices: limit positions; triangles counter-clockwise like the cage
    std::vector<Vec3> normals; ///< per vertex, the unit limit normal (from the limit tangents)
};

/// Uniform refinement to `level` (0..kMaxSubdivisionLevel), limit positions and normals at every
/// vertex of that level; each quad becomes two triangles split along its shorter diagonal (at
/// level 0, n-gons are fanned). Boundaries are interpolated (edges and corners sharp).
/// Validates the cage; throws Error on bad input or a level out of range.
LimitTessellation tessellate_limit(const ControlMesh& cage, int level);

/// The limit positions of the cage's own vertices.
std::vector<Vec3> limit_positions(const ControlMesh& cage);

/// A point of the limit surface from OpenSubdiv's exact evaluation (Bfr) of one cage face.
struct LimitSample {
    Vec3 p;
    Vec3 normal;     ///< unit dP/du x dP/dv (zero where that vanishes)
    uint32_t face;   ///< the cage face
    float s, t;      ///< its parameters in Bfr's parameterization of the face
};
/// Samples every cage face's limit surface at Bfr's uniform tessellation of rate `rate`
/// (rate + 1 points per edge, including the face's corners and borders). Exact except within
/// 1/256 of a face around an extraordinary vertex, where Bfr substitutes a Gregory patch.
std::vector<LimitSample> sample_limit_surface(const ControlMesh& cage, int rate);

/// How far the tessellation of a level lies from the limit surface.
struct TessellationError {
    double max_midpoint_deviation = 0;  ///< max over all triangle edges of |S(midpoint) - chord midpoint|
    double bound = 0;                   ///< kErrorBoundFactor * max_midpoint_deviation
};
/// The bound's factor: 4/3 is exact for surfaces quadratic over each triangle (the
/// interpolation error is then sum 4 l_i l_j m_k <= 4/3 max |m_k|); 2 leaves room for the
/// cubic terms and the irregular patches next to extraordinary vertices.
inline constexpr double kErrorBoundFactor = 2.0;
/// The deviation of the level-`level` tessellation (level >= 1) at the parametric midpoints of
/// every quad edge and both diagonals, taken exactly as the limit positions of the level + 1
/// vertices. Costs a refinement one level deeper than the tessellation.
TessellationError tessellation_error(const ControlMesh& cage, int level);

/// The kernel. Cheap to copy (the tessellation and its BVH are shared, immutable).
class SubdivisionSurface {
public:
    static constexpr const char* kName = "subdivision";

    /// Tessellates `cage` at `level` (see tessellate_limit) and builds the BVH.
    SubdivisionSurface(const ControlMesh& cage, int level);

    Aabb bounds() const;
    /// First crossing of the tessellation with t in [ray.tmin, tmax] (watertight triangle test);
    /// (u, v) are the barycentric weights of the hit triangle's vertices 1 and 2.
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const;
    /// The limit normals of the triangle nearest to p, interpolated (Phong) and normalized;
    /// (u, v) are not needed: the triangle is found from p with the BVH.
    Vec3 normal(Vec3 p, float u, float v) const;

    /// FNV-1a of the level and the tessellation (positions and indices): the scene fingerprint.
    uint64_t hash(uint64_t seed) const;

    int level() const;
    const LimitTessellation& tessellation() const;
    size_t triangle_count() const;
    /// Memory held: tessellation (positions, indices, normals), triangles and BVH.
    size_t bytes() const;

    struct Impl;

private:
    std::shared_ptr<const Impl> impl_;
};

static_assert(ShapeKernel<SubdivisionSurface>);

}  // namespace thicket
