#pragma once
/// What the bench measures: anything that builds over a scene and answers batches of rays.
/// Thicket's structures and the Embree backend both plug in here, so both are timed by the very
/// same loop on the very same ray arrays.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "thicket/accel/accel.h"
#include "thicket/accel/registry.h"
#include "thicket/core/ray.h"
#include "thicket/scene/scene.h"

namespace thicket {

/// Rays per parallel chunk in every tracer's trace loop: Accel's batch grain (large enough that the
/// shared counter is touched rarely, small enough that a slow region of the image does not leave one
/// thread working alone at the end). The bench also uses it to know how many threads a pass can keep busy.
inline constexpr size_t kTraceGrain = kBatchGrain;

/// Figures of the current build.
struct TracerFigures {
    std::string spec;            ///< canonical spec (or the backend's own name)
    size_t primitives = 0;
    size_t bytes = 0;            ///< all memory the built structure holds to answer queries
    size_t structure_bytes = 0;  ///< of which nodes and index arrays
    size_t primitive_bytes = 0;  ///< of which copies of the primitives (0 where they are not separable)
    size_t nodes = 0;            ///< 0 when the backend does not say
    double sah_cost = 0.0;       ///< 0 when undefined or unknown
};

class Tracer {
public:
    virtual ~Tracer() = default;

    /// The name the tables show: the spec as given, or "embree-medium" / "embree-high".
    virtual std::string name() const = 0;
    /// Whether build() uses the threads it is given. If not, the bench builds once and reports that
    /// build for every thread count.
    virtual bool parallel_build() const = 0;
    /// Builds over `scene` (which must outlive the tracer) with up to `threads` threads (0: all),
    /// replacing any earlier build; returns the build's wall time in milliseconds.
    virtual double build(const Scene& scene, unsigned threads) = 0;
    /// Figures of the current build.
    virtual TracerFigures figures() const = 0;

    /// Closest hit of rays[i] into hits[i] (same sizes) on `threads` threads (0: all). A miss has
    /// prim == kNoPrim. `coherent`: consecutive rays are neighbours (BatchOptions::coherent); a
    /// tracer may use it to trace them as packets.
    virtual void trace(std::span<const Ray> rays, std::span<Hit> hits, unsigned threads, bool coherent) const = 0;
    /// Any hit: out[i] = 1 if anything lies within [tmin, tmax] of rays[i], else 0.
    virtual void occluded(std::span<const Ray> rays, std::span<uint8_t> out, unsigned threads) const = 0;
    /// Whether its hits come from Thicket's own primitive tests, so that a hit on another
    /// primitive than the reference's can be checked by probing that primitive alone
    /// (PrimitiveProbe); false for other libraries, whose tests round differently.
    virtual bool hits_from_thicket_tests() const { return true; }
    /// Untimed counting pass: adds the nodes visited and primitives tested for every ray to
    /// `total`. Returns false, leaving `total` alone, when the tracer cannot count.
    virtual bool count(std::span<const Ray> rays, bool any_hit, RayCounters& total, unsigned threads) const = 0;
    /// Brings the current build up to date with `scene`, the scene it was built over with its
    /// vertices moved (Accel::refit), on up to `threads` threads; returns the wall time in
    /// milliseconds. The default throws Error: the tracer cannot refit (rebuild it instead).
    virtual double refit(const Scene& scene, unsigned threads);
};

/// A tracer to be made when its turn comes, so only one built structure lives at a time.
struct TracerFactory {
    std::string name;  ///< what the made tracer's name() returns
    std::function<std::unique_ptr<Tracer>()> make;
};

/// A tracer over build_accel(spec, ...); parallel_build() is the structure's
/// AccelInfo::threaded_build. Throws Error at once for an invalid spec.
std::unique_ptr<Tracer> make_accel_tracer(const std::string& spec);
/// The factory for make_accel_tracer(spec) (the spec is checked now, not when made).
TracerFactory accel_tracer_factory(const std::string& spec);
/// The same for a spec the caller has parsed already (`name` as asked, for the tables).
TracerFactory accel_tracer_factory(const std::string& name, const AccelSpec& parsed);

}  // namespace thicket
