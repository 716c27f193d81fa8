#pragma once
// The conformance suite's agreement rule, on top of the library's PrimitiveProbe.
#include "thicket/bench/primitive_probe.h"

namespace thicket::testing {

using thicket::identical_hits;
using thicket::PrimitiveProbe;

/// The agreement rule: both miss, or both hit the same primitive with identical t, u, v, or
/// another primitive that really is hit there: probing it alone gives exactly the reported t, u,
/// v, and that t equals the reference's within 1e-5 relative (several primitives tie).
bool same_closest_hit(const Hit& got, const Hit& want, const Ray& ray, const PrimitiveProbe& probe);

}  // namespace thicket::testing
