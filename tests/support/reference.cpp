#include "support/reference.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

#include "support/test_scenes.h"
#include "thicket/accel/registry.h"
#include "thicket/core/error.h"
#include "thicket/core/hash.h"
#include "thicket/util/atomic_file.h"
#include "thicket/util/parallel.h"

namespace thicket::testing {

namespace {

/// Where conformance processes share brute force's answers (THICKET_REFERENCE_CACHE, set by
/// ctest), or "" to keep them in this process only. Brute force costs rays x primitives; without
/// sharing, every structure family's process recomputed the same answers on every real scene.
std::string reference_cache_dir() {
    const char* dir = std::getenv("THICKET_REFERENCE_CACHE");
    return dir ? dir : "";
}

/// The cache file of one reference: named by a hash of everything the answers depend on (the
/// scene's geometry, the rays' bits, the triangle test), so a changed scene or ray generator
/// can never read stale answers. (A changed brute force cannot be seen here: the ctest fixture
/// conformance.references empties the cache at the start of every run.)
std::string cache_file(const std::string& dir, const Scene& scene, const std::string& isect,
                       const std::vector<Ray>& rays, size_t brute_stride) {
    uint64_t h = scene.fingerprint();
    h = fnv1a(isect.data(), isect.size(), h);
    h = fnv1a(&brute_stride, sizeof brute_stride, h);
    h = fnv1a(rays.data(), rays.size() * sizeof(Ray), h);
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.ref", static_cast<unsigned long long>(h));
    return dir + "/" + name;
}

bool read_cached(const std::string& file, Reference& ref) {
    std::ifstream in(file, std::ios::binary);
    if (!in) return false;
    const size_t n = ref.rays.size();
    ref.hits.resize(n);
    ref.occluded.resize(n);
    in.read(reinterpret_cast<char*>(ref.hits.data()), std::streamsize(n * sizeof(Hit)));
    in.read(reinterpret_cast<char*>(ref.occluded.data()), std::streamsize(n));
    if (ref.brute_stride > 1) {
        ref.brute_answered.resize(n);
        in.read(reinterpret_cast<char*>(ref.brute_answered.data()), std::streamsize(n));
        in.read(reinterpret_cast<char*>(&ref.fast_disagreements), sizeof ref.fast_disagreements);
    }
    // A file of another length is not ours: recompute rather than trust it.
    if (!in || in.peek() != std::char_traits<char>::eof()) {
        ref.hits.clear();
        ref.occluded.clear();
        ref.brute_answered.clear();
        ref.fast_disagreements = 0;
        return false;
    }
    return true;
}

void write_cached(const std::string& file, const Reference& ref) {
    std::string bytes(reinterpret_cast<const char*>(ref.hits.data()), ref.hits.size() * sizeof(Hit));
    bytes.append(reinterpret_cast<const char*>(ref.occluded.data()), ref.occluded.size());
    if (ref.brute_stride > 1) {
        bytes.append(reinterpret_cast<const char*>(ref.brute_answered.data()), ref.brute_answered.size());
        bytes.append(reinterpret_cast<const char*>(&ref.fast_disagreements), sizeof ref.fast_disagreements);
    }
    // Atomic: a family reading while another writes sees the whole file or none.
    write_file_atomically(file, bytes);
}

}  // namespace

namespace {
std::string describe(const Ray& r);
std::string describe(const Hit& h);
}  // namespace

const Reference& reference_for(const std::string& key, const Scene& scene, const std::string& isect, size_t count,
                               size_t brute_rays) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<Reference>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    auto& slot = cache[key + "|" + isect + "|" + std::to_string(count) + "|" + std::to_string(brute_rays)];
    if (!slot) {
        auto ref = std::make_unique<Reference>();
        ref->rays = conformance_rays(scene, count);
        ref->probe = std::make_shared<const PrimitiveProbe>(scene, isect);
        ref->brute = build_accel("brute:isect=" + isect, scene);
        const size_t n = ref->rays.size();
        ref->brute_stride = brute_rays >= n ? 1 : (n + brute_rays - 1) / std::max<size_t>(1, brute_rays);
        const std::string dir = reference_cache_dir();
        const std::string file = dir.empty() ? "" : cache_file(dir, scene, isect, ref->rays, ref->brute_stride);
        if (file.empty() || !read_cached(file, *ref)) {
            ref->hits.resize(n);
            ref->occluded.resize(n);
            const Accel& brute = *ref->brute;
            const size_t stride = ref->brute_stride;
            parallel_for((n + stride - 1) / stride, 16, 0, [&](size_t begin, size_t end) {
                for (size_t k = begin; k < end; ++k) {
                    ref->hits[k * stride] = brute.intersect(ref->rays[k * stride]);
                    ref->occluded[k * stride] = brute.occluded(ref->rays[k * stride]);
                }
            });
            if (stride > 1) {
                // Two fast references of independent code answer every ray; on brute force's rays
                // each must answer as it does, elsewhere brute force settles where they differ.
                const std::unique_ptr<Accel> fast[2] = {build_accel("bvh:isect=" + isect, scene),
                                                        build_accel("kdtree:isect=" + isect, scene)};
                ref->brute_answered.assign(n, 0);
                for (size_t i = 0; i < n; i += stride) ref->brute_answered[i] = 1;
                for (size_t i = 0; i < n; ++i) {
                    const Ray& r = ref->rays[i];
                    Hit h[2];
                    bool occ[2];
                    for (int f = 0; f < 2; ++f) {
                        h[f] = fast[f]->intersect(r);
                        occ[f] = fast[f]->occluded(r);
                        if (ref->from_brute(i) &&
                            (!same_closest_hit(h[f], ref->hits[i], r, *ref->probe) || occ[f] != bool(ref->occluded[i])))
                            throw Error(scene.name + ": the fast reference " + fast[f]->spec() +
                                        " disagrees with brute force on ray " + std::to_string(i) + " (" + describe(r) +
                                        "): " + describe(h[f]) + ", brute force " + describe(ref->hits[i]));
                    }
                    if (ref->from_brute(i)) continue;
                    if (same_closest_hit(h[1], h[0], r, *ref->probe) && occ[0] == occ[1]) {
                        ref->hits[i] = h[0];
                        ref->occluded[i] = occ[0];
                    } else {
                        ref->hits[i] = brute.intersect(r);
                        ref->occluded[i] = brute.occluded(r);
                        ref->brute_answered[i] = 1;
                        ++ref->fast_disagreements;
                    }
                }
                std::printf("[ judges   ] %s (%s): brute force answered %zu of %zu rays, bvh and kdtree agreed on the "
                            "rest but %zu, which brute force answered too\n",
                            scene.name.c_str(), isect.c_str(), (n + stride - 1) / stride, n, ref->fast_disagreements);
            }
            if (!file.empty()) write_cached(file, *ref);
        }
        slot = std::move(ref);
    }
    return *slot;
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

size_t most_tests_per_query(const Accel& accel, size_t primitives) {
    const AccelSpec spec = parse_accel_spec(accel.spec());
    // `mailbox=off` means what it says: a primitive in several cells is tested once per cell.
    if (spec.options.count("mailbox") && spec.get("mailbox") == "off") return SIZE_MAX;
    // (bvh8's quality=high is recorded as the builder=sbvh it stands for.)
    const bool spatial_splits = (spec.name == "bvh" || spec.name == "bvh8") && spec.get("builder") == "sbvh";
    if (!spatial_splits) return primitives;
    for (const auto& [key, value] : accel.stats().extra)
        if (key == "references") return std::max<size_t>(primitives, std::stoull(value));
    throw Error(accel.spec() + ": a spatial-split BVH without a 'references' figure");
}

std::string compare_with_reference(const Accel& accel, const Reference& ref, const std::string& scene_name) {
    const size_t most_tests = most_tests_per_query(accel, ref.probe->size());
    // The batch queries: rays grouped by direction octant and marked coherent, so that packet
    // kernels (bvh8) get whole packets of them; answers must be the per-ray ones.
    const size_t n = ref.rays.size();
    std::vector<size_t> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = i;
    auto octant = [&](size_t i) {
        const Vec3 d = ref.rays[i].dir;
        return int(std::signbit(d.x)) | int(std::signbit(d.y)) << 1 | int(std::signbit(d.z)) << 2;
    };
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return octant(a) < octant(b); });
    std::vector<Ray> grouped(n);
    for (size_t k = 0; k < n; ++k) grouped[k] = ref.rays[order[k]];
    std::vector<Hit> batch_hits(n);
    std::vector<uint8_t> batch_occluded(n);
    BatchOptions coherent;
    coherent.coherent = true;
    accel.intersect(grouped, batch_hits, coherent);
    accel.occluded(grouped, batch_occluded);  // any hit has no packet path: coherent is refused
    std::vector<Hit> batch_hit_of(n);
    std::vector<uint8_t> batch_occluded_of(n);
    for (size_t k = 0; k < n; ++k) {
        batch_hit_of[order[k]] = batch_hits[k];
        batch_occluded_of[order[k]] = batch_occluded[k];
    }

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
        Hit want = ref.hits[i];
        bool want_occluded = ref.occluded[i];
        if (!ref.from_brute(i) && (!same_closest_hit(plain, want, r, *ref.probe) || occ != want_occluded ||
                                   !same_closest_hit(batch_hit_of[i], want, r, *ref.probe))) {
            // The fast reference and this structure differ: brute force says which is right.
            want = ref.brute->intersect(r);
            want_occluded = ref.brute->occluded(r);
        }
        std::string what;
        if (!same_closest_hit(plain, want, r, *ref.probe))
            what = "closest hit " + describe(plain) + ", brute force " + describe(want);
        else if (!identical_hits(counted, plain))
            what = "counting pass differs: " + describe(counted) + " vs " + describe(plain);
        else if (!same_closest_hit(batch_hit_of[i], want, r, *ref.probe) || batch_hit_of[i].t != plain.t)
            what = "coherent batch " + describe(batch_hit_of[i]) + ", one ray at a time " + describe(plain);
        else if (bool(batch_occluded_of[i]) != occ)
            what = std::string("batch occluded ") + (batch_occluded_of[i] ? "yes" : "no") + ", one ray at a time " +
                   (occ ? "yes" : "no");
        else if (occ != want_occluded || occ_counted != occ)
            what = std::string("occluded ") + (occ ? "yes" : "no") + ", brute force " + (want_occluded ? "yes" : "no");
        else if (counters.prims > most_tests || occ_counters.prims > most_tests)
            what = "tested " + std::to_string(std::max(counters.prims, occ_counters.prims)) + " primitives of " +
                   std::to_string(ref.probe->size()) + ": some more than once";
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

bool sah_cost_explained(const AccelStats& stats) {
    return std::any_of(stats.extra.begin(), stats.extra.end(),
                       [](const auto& kv) { return kv.first == kSahUndefinedKey && !kv.second.empty(); });
}

}  // namespace thicket::testing
