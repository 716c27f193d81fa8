// Accel's double-precision entry points: refused by float structures, batched for double ones.
#include <string>

#include "thicket/accel/accel.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket {

namespace {

[[noreturn]] void refuse_double(const std::string& spec) {
    throw Error(float64_rays_refusal("double-precision rays", "structure '" + spec + "'", "trace float rays"));
}

}  // namespace

HitD Accel::intersect_double(const RayD&) const { refuse_double(spec()); }
bool Accel::occluded_double(const RayD&) const { refuse_double(spec()); }

void Accel::intersect_double(std::span<const RayD> rays, std::span<HitD> hits, const BatchOptions& options) const {
    check_ray_answers("closest-hit", rays.size(), hits.size());
    refuse_coherent("float64 closest-hit", options);  // no packet path in double
    if (!double_precision()) refuse_double(spec());
    parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) hits[i] = intersect_double(rays[i]);
        if (options.progress) options.progress(end - begin);
    });
}

void Accel::occluded_double(std::span<const RayD> rays, std::span<uint8_t> out, const BatchOptions& options) const {
    check_ray_answers("any-hit", rays.size(), out.size());
    refuse_coherent("float64 any-hit", options);
    if (!double_precision()) refuse_double(spec());
    parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) out[i] = occluded_double(rays[i]) ? 1 : 0;
        if (options.progress) options.progress(end - begin);
    });
}

}  // namespace thicket
