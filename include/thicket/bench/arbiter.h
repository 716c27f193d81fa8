#pragma once
/// Settles a disagreement between two answers on one ray in double precision, where float
/// rounding decides: an edge ray (the ray passes within rounding of a triangle's boundary), a
/// distance off by the rounding of a ray starting near the surface it hits, or a hit the
/// reference missed (Embree 3.13 misses some hits well inside the triangles of mirrored
/// instances: BENCHMARKS.md, "Agreement").
///
/// Each triangle an answer names is carried to the world in double (an instance's through its
/// transform) and tested against the float ray taken exactly. Rounding is bounded by
///   delta(t) = kArbiterUlps * 2^-24 * (|org|_inf + |t| |dir|_inf) * max(1, cond / 3),
/// a distance in world units (cond: the instance transform's condition number, 3 for a rotation
/// with uniform scale). A hit at t is *possible* when the point org + t dir lies within delta(t)
/// of its triangle; a triangle is hit *for certain* when every ray within delta(t*) of this one
/// (moved sideways) crosses it, at a t* at least delta(t*) inside the ray's interval.
///
/// The candidate's answer is right within rounding when its hit (if any) is possible and the
/// reference's hit, wherever it is nearer than the candidate's (or the candidate misses), is not
/// certain. A candidate that drops a hit inside a triangle, invents one, or names a far-off t is
/// still a disagreement. Shapes (spheres, patches, ...) are never arbitrated: no exact test here.
#include <cstddef>
#include <cstdint>
#include <optional>

#include "thicket/core/ray.h"
#include "thicket/core/vec3.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// Units in the last place (of the ray's coordinates) a float pipeline may lose; observed edge
/// rays between Thicket and Embree lie within 1.7 of them.
inline constexpr double kArbiterUlps = 8.0;

class RoundingArbiter {
public:
    /// Arbitrates answers on `scene` (which must outlive the arbiter); hit ids are flattened ids
    /// for a scene with instances, as the structures report them.
    explicit RoundingArbiter(const Scene& scene);

    /// Whether `candidate` is right within rounding where it disagrees with `reference` (the rule
    /// above). False when either names a shape or an id outside the scene.
    bool candidate_within_rounding(const Ray& ray, const Hit& reference, const Hit& candidate) const;

    /// How a triangle meets a ray in exact arithmetic (for tests and reports).
    struct Verdict {
        bool triangle = false;  ///< the id names a triangle of the scene (else the rest is unset)
        double t = 0.0;         ///< where the ray meets the triangle's plane (NaN: parallel)
        double depth = 0.0;     ///< how far sideways the ray may move and still cross it (< 0: misses by that much)
        double point_distance = 0.0;  ///< distance of org + t_asked * dir from the triangle
        double delta = 0.0;           ///< delta(t) at t_asked
        double scale = 1.0;           ///< max(1, cond / 3) of the triangle's instance
    };
    /// The exact meeting of `ray` and primitive `prim`, with the point at `t_asked`.
    Verdict judge(const Ray& ray, uint32_t prim, double t_asked) const;

    /// A possible hit: the point at t lies within delta(t) of the triangle.
    bool possible(const Ray& ray, const Hit& hit) const;
    /// A certain hit: the rule above, at the triangle's exact t.
    bool certain(const Ray& ray, uint32_t prim) const;

private:
    struct Triangle {
        Vec3d v[3];          ///< in the world, in double
        double scale = 1.0;  ///< max(1, cond / 3) of its instance's transform, 1 without instances
    };
    std::optional<Triangle> triangle(uint32_t prim) const;
    /// delta(t) of the rule above for a triangle of that scale.
    static double delta(const Ray& ray, double t, double scale);

    const Scene& scene_;
};

}  // namespace thicket
