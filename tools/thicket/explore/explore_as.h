#pragma once
// Which structure an Accel is, for the explore pages that read a structure's own data (its
// drawing, its tetrahedra) or call its traversal templates with a recorder.
#include "thicket/accel/accel.h"
#include "thicket/prims/primitive_set.h"
#include "thicket/prims/mixed.h"
#include "thicket/prims/triangles.h"

namespace thicket::explore {

/// Calls f(structure) when `accel` is Structure<Set>; returns whether it was.
template <template <PrimitiveSet> class Structure, class Set, class F>
bool as_over(const Accel& accel, F& f) {
    const auto* p = dynamic_cast<const Structure<Set>*>(&accel);
    if (p) f(*p);
    return p != nullptr;
}

/// Calls f(structure) when `accel` is Structure<P> for one of the primitive sets the registry
/// builds over (with_primitives in accel/dispatch.h); returns whether it was. (Structure<Set> is
/// named only where both are template parameters: clang 14 crashes checking the constraint of
/// Structure<Triangles<...>> written with a concrete set in a template's body.)
template <template <PrimitiveSet> class Structure, class F>
bool as(const Accel& accel, F&& f) {
    return as_over<Structure, Triangles<TriangleTest::Moller>>(accel, f) ||
           as_over<Structure, Triangles<TriangleTest::Watertight>>(accel, f) ||
           as_over<Structure, MixedPrimitives>(accel, f);
}

}  // namespace thicket::explore
