#include "support/probe.h"

#include <cmath>

namespace thicket::testing {

bool same_closest_hit(const Hit& got, const Hit& want, const Ray& ray, const PrimitiveProbe& probe) {
    if (got.found() != want.found()) return false;
    if (!got.found()) return true;
    if (got.prim == want.prim) return identical_hits(got, want);
    return std::fabs(got.t - want.t) <= 1e-5f * std::fabs(want.t) && identical_hits(probe.hit(got.prim, ray), got);
}

}  // namespace thicket::testing
