#pragma once
// An independent reference for triangle scenes: the closest hit in double precision over every
// triangle, with no filter at all (no degenerate-triangle rule, no box check). Brute force and
// every structure share the plausibility filter (Triangles::plausible); comparing brute force with
// this reference is what shows the filter drops only the ill-conditioned hits the README describes
// (a ray grazing a triangle or a needle of one, a hit on an edge or at the end of the interval),
// and never a genuine one.
#include <cstddef>
#include <span>
#include <string>

#include "thicket/core/ray.h"
#include "thicket/scene/scene.h"

namespace thicket::testing {

struct FilterCheck {
    size_t rays = 0;
    size_t agree = 0;            ///< same answer (or a tie at the same t within 1e-5 relative)
    size_t ill_conditioned = 0;  ///< differ, on a hit that is ill-conditioned (explained)
    size_t filter_rejections = 0;  ///< of those: the float test reports the hit, the filter drops it
    size_t unexplained = 0;      ///< differ on a well-conditioned hit: a wrong answer
    std::string first_unexplained;
};

/// Compares closest hits `hits` of `rays` over the triangles of `scene` (no shapes), found with
/// the float test `isect` ("moller" or "watertight"), with the double-precision reference, and
/// explains every difference or counts it unexplained.
FilterCheck check_against_double_reference(const Scene& scene, const std::string& isect, std::span<const Ray> rays,
                                           std::span<const Hit> hits);

/// The named-primitive check, one triangle per ray: every hit in `hits` must name a triangle of
/// `scene` (no shapes) that `ray`, in double precision, crosses inside its interval at the hit's t
/// (within 1e-5 of t's rounding scale), unless that crossing is ill-conditioned (as above). Cheap
/// enough for every ray of a real scene, and shares no code with the structures. Counts in
/// FilterCheck: agree = confirmed, ill_conditioned = explained, unexplained = a wrong primitive or
/// t; misses are not counted.
FilterCheck check_named_primitives(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits);

}  // namespace thicket::testing
