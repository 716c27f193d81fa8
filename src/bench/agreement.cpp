#include "thicket/bench/agreement.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "thicket/core/error.h"

namespace thicket {

namespace {

void check_sizes(size_t reference, size_t candidate, size_t index) {
    const size_t expected = index ? index : reference;
    if (candidate != expected)
        throw Error("agreement: " + std::to_string(candidate) + " answers to compare with " +
                    std::to_string(expected) + " reference answers");
}

size_t reference_index(std::span<const uint32_t> index, size_t i, size_t reference_size) {
    const size_t r = index.empty() ? i : size_t(index[i]);
    if (r >= reference_size) throw Error("agreement: sample index " + std::to_string(r) + " out of range");
    return r;
}

}  // namespace

bool hits_agree(const Hit& reference, const Hit& candidate, const TieCheck& tie_is_real, size_t ray) {
    if (reference.found() != candidate.found()) return false;
    if (!reference.found()) return true;
    const double a = reference.t, b = candidate.t;
    const double dt = std::fabs(a - b), scale = std::max(std::fabs(a), std::fabs(b));
    if (reference.prim == candidate.prim) return dt <= kSamePrimitiveTolerance * scale;
    return dt <= kTieTolerance * scale && (!tie_is_real || tie_is_real(ray, candidate));
}

Agreement compare_hits(std::span<const Hit> reference, std::span<const Hit> candidate,
                       std::span<const uint32_t> index, const TieCheck& tie_is_real, const HitArbiter& arbiter) {
    check_sizes(reference.size(), candidate.size(), index.size());
    Agreement a;
    a.rays = candidate.size();
    for (size_t i = 0; i < candidate.size(); ++i) {
        const Hit& ref = reference[reference_index(index, i, reference.size())];
        const Hit& c = candidate[i];
        if (!hits_agree(ref, c, tie_is_real, i)) {
            if (arbiter && arbiter(i, ref, c)) {
                ++a.agreeing, ++a.arbitrated;  // right within rounding; its distance is not the rule's
                continue;
            }
            if (a.first_mismatch == std::numeric_limits<size_t>::max()) a.first_mismatch = i;
            continue;  // counted as a disagreement: its distance says nothing about precision
        }
        ++a.agreeing;
        if (ref.found() && c.found()) {
            const double dt = std::fabs(double(c.t) - double(ref.t));
            const double scale = std::max(std::fabs(double(c.t)), std::fabs(double(ref.t)));
            // A NaN distance must show up, not vanish in max(): report it as infinite.
            a.max_dt = std::isnan(dt) ? INFINITY : std::max(a.max_dt, dt);
            if (scale > 0.0) a.max_dt_rel = std::isnan(dt) ? INFINITY : std::max(a.max_dt_rel, dt / scale);
        }
    }
    return a;
}

Agreement compare_occlusion(std::span<const uint8_t> reference, std::span<const uint8_t> candidate,
                            std::span<const uint32_t> index, const FlagArbiter& arbiter) {
    check_sizes(reference.size(), candidate.size(), index.size());
    Agreement a;
    a.rays = candidate.size();
    for (size_t i = 0; i < candidate.size(); ++i) {
        const bool ref = reference[reference_index(index, i, reference.size())] != 0;
        if (ref == (candidate[i] != 0))
            ++a.agreeing;
        else if (arbiter && arbiter(i))
            ++a.agreeing, ++a.arbitrated;
        else if (a.first_mismatch == std::numeric_limits<size_t>::max())
            a.first_mismatch = i;
    }
    return a;
}

}  // namespace thicket
