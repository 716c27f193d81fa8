#pragma once
/// Ray-for-ray comparison of a structure's answers with a reference's (Embree-high in the bench).
///
/// Two closest-hit answers agree when both miss, or both hit and either name the same primitive
/// at distances within kSamePrimitiveTolerance (rounding of different intersection tests), or lie
/// at the same distance within kTieTolerance relative: a tie, where two primitives meet (a shared
/// edge, coplanar overlaps) and either answer is right, provided the named primitive really is hit
/// there (the TieCheck, when the candidate's hits come from Thicket's own tests). Two any-hit
/// answers agree when both flags are equal. A ray that fails this rule still agrees when an arbiter
/// (the bench's RoundingArbiter, bench/arbiter.h) shows the candidate's answer right within float
/// rounding (a ray at the mesh's outer edge: bench/arbiter.h); such rays are counted apart. The
/// largest t difference over the agreeing rays is reported as well.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>

#include "thicket/core/ray.h"

namespace thicket {

inline constexpr double kTieTolerance = 1e-4;
/// Two answers on the same primitive agree only within this relative distance: different
/// triangle tests round differently (by 2.6e-5 at most on the shared scenes; a grazing ray can
/// reach 4.2e-4, BENCHMARKS.md), but a t off by more is a wrong answer, not rounding.
inline constexpr double kSamePrimitiveTolerance = 1e-3;

/// Whether candidate hit `candidate` (on ray `ray`, an index into the compared answers) is really
/// a hit of the primitive it names: probing that primitive alone gives its t, u, v.
using TieCheck = std::function<bool(size_t ray, const Hit& candidate)>;

/// Whether the candidate's answer on ray `ray` is right within rounding where it disagrees with
/// the reference's by the rule above.
using HitArbiter = std::function<bool(size_t ray, const Hit& reference, const Hit& candidate)>;
/// The same for any-hit answers: the flags differ on ray `ray`.
using FlagArbiter = std::function<bool(size_t ray)>;

struct Agreement {
    size_t rays = 0;
    size_t agreeing = 0;
    size_t arbitrated = 0;  ///< of the agreeing rays, those only the arbiter accepted
    double max_dt = 0.0;      ///< largest |t - t_ref| over agreeing rays where both hit
    double max_dt_rel = 0.0;  ///< largest |t - t_ref| / max(|t|, |t_ref|) over the same rays
    size_t first_mismatch = std::numeric_limits<size_t>::max();  ///< index of the first disagreement

    size_t disagreeing() const { return rays - agreeing; }
    /// Agreement in percent; 100 for no rays.
    double percent() const { return rays ? 100.0 * double(agreeing) / double(rays) : 100.0; }
};

/// Whether two closest-hit answers agree by the rule above; a tie (other primitive) also needs
/// `tie_is_real(ray, candidate)` when one is given.
bool hits_agree(const Hit& reference, const Hit& candidate, const TieCheck& tie_is_real = {}, size_t ray = 0);

/// Compares closest-hit answers ray by ray; candidate[i] is compared with reference[index[i]]
/// when `index` is given (a sample of the reference's rays), else with reference[i]. Sizes must
/// match (throws Error otherwise). `arbiter`, when given, is asked about every ray the rule rejects.
Agreement compare_hits(std::span<const Hit> reference, std::span<const Hit> candidate,
                       std::span<const uint32_t> index = {}, const TieCheck& tie_is_real = {},
                       const HitArbiter& arbiter = {});
/// The same for any-hit answers (0 or 1 per ray).
Agreement compare_occlusion(std::span<const uint8_t> reference, std::span<const uint8_t> candidate,
                            std::span<const uint32_t> index = {}, const FlagArbiter& arbiter = {});

}  // namespace thicket
