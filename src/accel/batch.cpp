// Accel's batch queries: one parallel loop for every structure; what a thread does with its share
// is the structure's (intersect_chunk / occluded_chunk).
#include <string>

#include "thicket/accel/accel.h"
#include "thicket/core/error.h"
#include "thicket/util/parallel.h"

namespace thicket {

namespace {

void check_sizes(const char* query, size_t rays, size_t answers) {
    if (rays != answers)
        throw Error(std::string(query) + " batch: " + std::to_string(rays) + " rays but room for " +
                    std::to_string(answers) + " answers");
}

}  // namespace

void Accel::intersect(std::span<const Ray> rays, std::span<Hit> hits, const BatchOptions& options) const {
    check_sizes("closest-hit", rays.size(), hits.size());
    parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        intersect_chunk(rays.subspan(begin, end - begin), hits.subspan(begin, end - begin), options.coherent);
        if (options.progress) options.progress(end - begin);
    });
}

void Accel::occluded(std::span<const Ray> rays, std::span<uint8_t> out, const BatchOptions& options) const {
    check_sizes("any-hit", rays.size(), out.size());
    parallel_for(rays.size(), kBatchGrain, options.threads, [&](size_t begin, size_t end) {
        occluded_chunk(rays.subspan(begin, end - begin), out.subspan(begin, end - begin), options.coherent);
        if (options.progress) options.progress(end - begin);
    });
}

void Accel::intersect_chunk(std::span<const Ray> rays, std::span<Hit> hits, bool) const {
    for (size_t i = 0; i < rays.size(); ++i) hits[i] = intersect(rays[i]);
}

void Accel::occluded_chunk(std::span<const Ray> rays, std::span<uint8_t> out, bool) const {
    for (size_t i = 0; i < rays.size(); ++i) out[i] = occluded(rays[i]) ? 1 : 0;
}

}  // namespace thicket
