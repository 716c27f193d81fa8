#pragma once
/// Which coherent rays the packet kernels (KernelTable::packet_closest) may take: the baseline
/// side of their precondition.
#include <cstdint>

#include "thicket/core/ray.h"

namespace thicket::bvh8 {

/// Whether rays[0..count) share one direction octant and have a finite 1/dir on every axis
/// (computed as the kernels compute it).
bool packet_eligible(const Ray* rays, uint32_t count);

}  // namespace thicket::bvh8
