#include "support/reference.h"

#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"

namespace thicket::testing {

const Reference& reference_for(const std::string& key, const Scene& scene, const std::string& isect, size_t count) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<Reference>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    auto& slot = cache[key + "|" + isect + "|" + std::to_string(count)];
    if (!slot) {
        slot = std::make_unique<Reference>();
        slot->rays = conformance_rays(scene, count);
        auto brute = build_accel("brute:isect=" + isect, scene);
        for (const Ray& r : slot->rays) {
            slot->hits.push_back(brute->intersect(r));
            slot->occluded.push_back(brute->occluded(r));
        }
    }
    return *slot;
}

bool same_closest_hit(const Hit& got, const Hit& want) {
    if (got.found() != want.found()) return false;
    if (!got.found()) return true;
    if (got.prim == want.prim) return got.t == want.t && got.u == want.u && got.v == want.v;
    return std::fabs(got.t - want.t) <= 1e-5f * std::fabs(want.t);
}

namespace {

std::string describe(const Ray& r) {
    std::ostringstream s;
    s.precision(9);
    s << "org (" << r.org.x << ", " << r.org.y << ", " << r.org.z << ") dir (" << r.dir.x << ", " << r.dir.y << ", "
      << r.dir.z << ") t in [" << r.tmin << ", " << r.tmax << "]";
    return s.str();
}

std::string describe(const Hit& h) {
    if (!h.found()) return "miss";
    std::ostringstream s;
    s.precision(9);
    s << "prim " << h.prim << " t " << h.t << " uv (" << h.u << ", " << h.v << ")";
    return s.str();
}

}  // namespace

std::string compare_with_reference(const Accel& accel, const Reference& ref, const std::string& scene_name) {
    std::ostringstream errors;
    size_t bad = 0;
    for (size_t i = 0; i < ref.rays.size(); ++i) {
        const Ray& r = ref.rays[i];
        const Hit plain = accel.intersect(r);
        RayCounters counters;
        const Hit counted = accel.intersect(r, counters);
        const bool occ = accel.occluded(r);
        RayCounters occ_counters;
        const bool occ_counted = accel.occluded(r, occ_counters);
        std::string what;
        if (!same_closest_hit(plain, ref.hits[i]))
            what = "closest hit " + describe(plain) + ", brute force " + describe(ref.hits[i]);
        else if (!same_closest_hit(counted, plain) || counted.prim != plain.prim)
            what = "counting pass differs: " + describe(counted) + " vs " + describe(plain);
        else if (occ != bool(ref.occluded[i]) || occ_counted != occ)
            what = std::string("occluded ") + (occ ? "yes" : "no") + ", brute force " + (ref.occluded[i] ? "yes" : "no");
        else if (counters.prims > 0 && counters.nodes == 0 && accel.spec().rfind("brute", 0) != 0)
            what = "counters report primitive tests but no node visits";
        if (!what.empty() && bad++ < 5)
            errors << "  " << scene_name << " ray " << i << " (" << describe(r) << "): " << what << "\n";
    }
    if (bad == 0) return "";
    std::ostringstream out;
    out << accel.spec() << " disagrees with brute force on " << bad << " of " << ref.rays.size() << " rays:\n"
        << errors.str();
    return out.str();
}

}  // namespace thicket::testing
