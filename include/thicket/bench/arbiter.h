#pragma once
/// Settles a disagreement between two answers on one ray in double precision, where float
/// rounding decides: an edge ray (the ray passes within rounding of the mesh's boundary, or of a
/// crack a fold opens), a distance off by the rounding of a ray starting near the surface it hits.
/// Nothing else: a hit either side drops where the mesh is certain to be crossed, an invented
/// hit, a hit outside the ray's interval, or a hit the reference misses well inside a triangle
/// (Embree 3.13 misses some inside mirrored instances: BENCHMARKS.md, "Agreement") stays a
/// disagreement, counted in the report.
///
/// Each triangle an answer names is carried to the world in double (an instance's through its
/// transform) and tested against the float ray taken exactly. Rounding is bounded by
///   delta(t) = kArbiterUlps * 2^-24 * (|org|_inf + |t| |dir|_inf) * min(kArbiterMaxScale, max(1, cond / 3)),
/// a distance in world units (cond: the instance transform's condition number, 3 for a rotation
/// with uniform scale). A hit at t is *possible* when t lies in [tmin, tmax] widened by
/// delta(t) / |dir| and the point org + t dir lies within delta(t) of its triangle. A hit is
/// *certain* when every ray within delta(t) of this one (moved sideways) crosses the triangle or
/// one of the mesh's triangles around its vertices (vertices welded by position): the union of
/// those, projected across the ray, holds the ray and lies delta(t) around it except across an
/// edge exactly two of them share from its two sides; and every such crossing lies at least
/// delta(t) inside the ray's interval. So a ray through the shared edge of two triangles is
/// certain to hit one of them, and a structure that finds neither is wrong.
///
/// Two closest hits agree within rounding when the candidate's hit (if any) is possible and
/// neither side skipped a certain hit nearer than its own answer (farther than the skipped
/// union's crossings by more than rounding, or a miss). Any-hit answers are settled on any-hit
/// answers (occlusion_within_rounding). Shapes (spheres, patches, ...) are never arbitrated: no
/// exact test here.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "thicket/core/ray.h"
#include "thicket/core/vec3.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// Units in the last place (of the ray's coordinates) a float pipeline may lose; observed edge
/// rays between Thicket and Embree lie within 1.7 of them.
inline constexpr double kArbiterUlps = 8.0;
/// The most an instance's conditioning may widen delta: a transform worse than cond 48 is not
/// forgiven more than that (kMaxTransformCondition allows 1e4, which widened it 3,333 times).
inline constexpr double kArbiterMaxScale = 16.0;

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

    /// Whether the candidate's any-hit answer `candidate_occluded` is right within rounding where
    /// it differs from the reference's, given each structure's closest hit within the ray's
    /// interval: a "no" is right when neither closest hit is certain (the candidate's own closest
    /// hit counts, so a broken any-hit path shows); a "yes" when the candidate's closest hit is
    /// possible and not certain (a certain one the reference missed is its disagreement).
    bool occlusion_within_rounding(const Ray& ray, bool candidate_occluded, const Hit& reference_closest,
                                   const Hit& candidate_closest) const;

    /// A possible hit: t within the ray's interval and the point at t within delta(t) of the
    /// triangle, both widened by rounding only.
    bool possible(const Ray& ray, const Hit& hit) const;
    /// A certain hit: the rule above, over the triangle and the mesh's triangles around it.
    bool certain(const Ray& ray, uint32_t prim) const;

private:
    struct Triangle {
        Vec3d v[3];          ///< in the world, in double
        double scale = 1.0;  ///< min(kArbiterMaxScale, max(1, cond / 3)) of its instance, 1 without
    };
    /// Where a primitive id's triangle is: the mesh's triangle and the instance placing it.
    struct Located {
        uint32_t triangle = 0;
        const Instance* instance = nullptr;
        double scale = 1.0;
    };
    struct Certainty {
        bool certain = false;
        double t_far = 0.0;    ///< the farthest crossing a ray within rounding may make
        double slack_t = 0.0;  ///< delta there, in units of t
    };
    std::optional<Located> locate(uint32_t prim) const;
    Triangle world(const Located& at, uint32_t mesh_triangle) const;
    std::optional<Triangle> triangle(uint32_t prim) const;
    Certainty certainty(const Ray& ray, uint32_t prim) const;
    /// `nearer` is a certain hit nearer than `other` (a miss, or farther than its crossings).
    bool skipped_certain_hit(const Ray& ray, const Hit& nearer, const Hit& other) const;
    /// delta(t) of the rule above for a triangle of that scale.
    static double delta(const Ray& ray, double t, double scale);

    const Scene& scene_;
    std::vector<uint32_t> welded_;      ///< per mesh vertex: the first vertex at its exact position
    std::vector<uint32_t> ring_first_;  ///< per welded vertex: where its triangles start in ring_
    std::vector<uint32_t> ring_;        ///< the mesh triangles around each welded vertex
};

}  // namespace thicket
