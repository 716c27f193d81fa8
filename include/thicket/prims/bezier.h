#pragma once
/// The bicubic Bezier patch as a shape kernel (see shape.h), intersected directly: recursive
/// subdivision in ray space with Newton iteration once a sub-patch provably holds at most one
/// root (docs/bezier-subdivision.md has the algorithm and its tolerances).
#include <array>
#include <cstddef>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"
#include "thicket/prims/shape.h"

namespace thicket {

/// Surface point and first partial derivatives of a patch at (u, v).
struct BezierSample {
    Vec3 p, du, dv;
};

/// P(u, v) = sum over i, j of B_i(u) B_j(v) * control_point(i, j), with B the cubic Bernstein
/// polynomials; i runs along u (a row of the 4x4 grid), j along v. The kernel's normal is
/// dP/du x dP/dv: for the teapot that is outward.
class BezierPatch {
public:
    static constexpr const char* kName = "bezier";

    using ControlPoints = std::array<Vec3, 16>;  ///< index 4 * j + i: row j (v), column i (u)

    /// A patch with all 16 control points at the origin. A patch whose control points all
    /// coincide has no area and is never hit.
    BezierPatch() = default;
    /// Throws Error if a coordinate is NaN or infinite.
    explicit BezierPatch(const ControlPoints& cp);

    const ControlPoints& control_points() const { return cp_; }
    Vec3 control_point(int i, int j) const { return cp_[4 * j + i]; }

    /// Bounds of the 16 control points: conservative (the convex hull holds the surface).
    Aabb bounds() const { return bounds_; }
    /// First crossing with t in [ray.tmin, tmax] (see the class comment of bezier.cpp for the
    /// guarantees); fills t and the patch parameters (u, v) in [0, 1].
    bool intersect(const Ray& ray, float tmax, ShapeHit& hit) const;
    /// Unit dP/du x dP/dv at (u, v); where that vanishes (a collapsed edge, like the teapot's lid
    /// and bottom centres) its limit from inside the patch. Always finite. p is unused.
    Vec3 normal(Vec3 p, float u, float v) const;

    /// P, dP/du and dP/dv at (u, v), evaluated in double and rounded.
    BezierSample evaluate(float u, float v) const;
    Vec3 point(float u, float v) const { return evaluate(u, v).p; }

    /// Memory of one patch: control points and cached bounds, no per-patch hierarchy.
    static constexpr size_t bytes() { return sizeof(BezierPatch); }

private:
    ControlPoints cp_{};
    Aabb bounds_{Vec3(0.0f), Vec3(0.0f)};
};

static_assert(ShapeKernel<BezierPatch>);

/// What one intersect() call did, for tests and statistics (filled by intersect_counted).
struct BezierQueryStats {
    int subpatches = 0;    ///< sub-patches whose ray-space box was tested
    int newton_runs = 0;   ///< Newton iterations started
    bool budget_hit = false;///< the sub-patch budget ran out (rays lying in the surface)
};

/// intersect() that also reports its work.
bool intersect_counted(const BezierPatch& patch, const Ray& ray, float tmax, ShapeHit& hit, BezierQueryStats& stats);

}  // namespace thicket
