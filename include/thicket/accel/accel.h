#pragma once
/// The one interface every acceleration structure implements: bounds, closest hit, any hit,
/// statistics. Structures are interchangeable behind it at one virtual call per ray (or per batch):
/// inside, each traversal is compiled for its primitive set, with no virtual call per node (the
/// instanced top level calls its bottom levels through function pointers, once per instance a ray
/// reaches). For the last few percent, use a structure's class directly.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/closest_point.h"
#include "thicket/core/drawn_node.h"
#include "thicket/core/ray.h"
#include "thicket/core/ray_box.h"
#include "thicket/core/sah.h"
#include "thicket/core/traversal_record.h"
#include "thicket/core/tree_figures.h"

namespace thicket {

struct Scene;

/// The AccelStats::extra key under which a structure that leaves sah_cost at 0 (undefined) says
/// why; the conformance suite requires it whenever sah_cost is 0 for a scene with primitives.
inline constexpr const char* kSahUndefinedKey = "SAH cost undefined";

/// The AccelStats::extra key under which a structure that could not take the scene the way it is
/// designed to (a tetrahedralization refused, a size limit reached) says why and what it did
/// instead; the conformance suite prints it next to the scene.
inline constexpr const char* kLimitedKey = "limited because";

struct AccelStats {
    std::string spec;          ///< canonical spec string of the structure
    size_t primitives = 0;
    size_t nodes = 0;          ///< all nodes (or cells) in use
    size_t leaves = 0;
    size_t max_depth = 0;
    size_t bytes = 0;          ///< structure memory: nodes and index arrays, not the primitives
    size_t primitive_bytes = 0;///< memory of the primitive data the structure holds
    double sah_cost = 0.0;     ///< with kSahTraversalCost, kSahIntersectionCost; 0 if undefined (see kSahUndefinedKey)
    double build_ms = 0.0;
    std::vector<std::pair<std::string, std::string>> extra;  ///< structure-specific figures
};

/// A block of a reordered batch is sorted when its second chunk took at least this long a ray as
/// given (accel/ray_order.h: the sort costs about 10 ns a ray, and cheaper rays gain nothing).
inline constexpr double kReorderFromNs = 200.0;

/// How a batch of rays is traced (Accel::intersect / occluded over spans).
struct BatchOptions {
    unsigned threads = 0;  ///< 0: all cores
    /// A hint that consecutive rays are neighbours (a camera's pixels in small tiles): structures
    /// with a packet path (bvh8) trace groups of them together. The answers are the same either way.
    /// Closest-hit batches only: the any-hit, crossing and closest-point batches have no coherent
    /// path and refuse it (refuse_coherent), so that a hint which changes nothing is not taken for one
    /// that did.
    bool coherent = false;
    /// True: batches of at least kReorderMin rays that are not coherent are traced in blocks, each
    /// block sorted by direction octant and origin (accel/ray_order.h) when its second chunk took
    /// at least reorder_from_ns a ray, and each answer written back to its ray's place: the same
    /// answers, 1.05-1.13x faster on the interior scenes' diffuse and random sets, but 0.83-0.89x
    /// on the dragon's diffuse rays (BENCHMARKS.md, "Reordered batches"), hence off by default.
    bool reorder = false;
    /// The cost a ray (nanoseconds, as the second chunk of a block measures it) from which that
    /// block is sorted: 0 sorts every block.
    double reorder_from_ns = kReorderFromNs;
    /// Called with the number of rays just finished, from whichever thread finished them (for a
    /// progress bar); may be empty. Must not throw.
    std::function<void(size_t)> progress;
};

/// Throws Error naming `query` when options.coherent is set for a batch without a coherent path.
void refuse_coherent(const char* query, const BatchOptions& options);
/// Throws Error naming `query` when a batch of `rays` rays has room for `answers` answers, another number.
void check_ray_answers(const char* query, size_t rays, size_t answers);

/// Two hits of one ray whose t differ by at most this much relative are one surface crossing
/// (all_hits, count_hits): a ray through an edge or vertex shared by several triangles of a closed
/// mesh hits each of them at the same t, up to the triangle test's rounding, and crosses once.
/// The same tolerance as the conformance suite's "another primitive hit at the same t".
inline constexpr float kSameCrossing = 1e-5f;

/// The smallest t after `t` that starts a new crossing, with the spacing of t's precision.
template <class S>
inline S next_crossing_t(S t) {
    return std::nextafter(t + S(kSameCrossing) * std::fabs(t), std::numeric_limits<S>::infinity());
}

/// Appends the crossings of `ray` within [ray.tmin, ray.tmax] to `out`, nearest first, as
/// closest(ray) answers them: the closest hit, then the closest from just past it, past every
/// hit of one crossing (neighbours at a shared edge answer the same t, or a few ulps apart:
/// kSameCrossing), until a miss. The interval must shrink, or a structure answering a hit before
/// tmin would loop forever; a t that cannot grow (inf) ends the ray.
template <class S, class Closest>
inline void step_crossings(RayT<S> ray, Closest&& closest, std::vector<HitT<S>>& out) {
    for (;;) {
        const HitT<S> hit = closest(ray);
        if (!hit.found()) return;
        out.push_back(hit);
        const S next = next_crossing_t(hit.t);
        if (!(next > ray.tmin) || !(next <= ray.tmax) || !std::isfinite(next)) return;
        ray.tmin = next;
    }
}

/// Sorts `hits` by t (then primitive) and merges them into crossings as Accel::all_hits steps from
/// one to the next: a hit before next_crossing_t of the last crossing kept is the same crossing.
/// Appends the crossings to *out (when out is not null) and returns how many there are.
size_t merge_crossings(std::span<Hit> hits, std::vector<Hit>* out);

/// Every crossing of each ray of a batch: the hits of rays[i] are hits[splits[i] .. splits[i+1]),
/// sorted by t (Open3D's ray_splits layout; splits has one entry more than there are rays).
template <class S>
struct HitListsOf {
    std::vector<size_t> splits;
    std::vector<HitT<S>> hits;
};
using HitLists = HitListsOf<float>;
using HitListsD = HitListsOf<double>;  ///< float64 rays' (query/double_rays.h)

/// Rays per unit of work in a batch: a multiple of every packet size, small enough that a slow
/// region of the image does not leave one thread working alone at the end.
inline constexpr size_t kBatchGrain = 256;

class Accel {
public:
    virtual ~Accel() = default;

    /// Bounds of everything the structure holds (empty box for an empty scene).
    virtual Aabb bounds() const = 0;
    /// Closest hit within [ray.tmin, ray.tmax]; result.prim == kNoPrim on a miss.
    virtual Hit intersect(const Ray& ray) const = 0;
    /// Same, counting nodes visited and primitives tested into `counters`.
    virtual Hit intersect(const Ray& ray, RayCounters& counters) const = 0;
    /// Is anything hit within [ray.tmin, ray.tmax]? Stops at the first hit found.
    virtual bool occluded(const Ray& ray) const = 0;
    virtual bool occluded(const Ray& ray, RayCounters& counters) const = 0;
    virtual AccelStats stats() const = 0;

    /// Closest hit, recording the traversal into `recorder` (core/traversal_record.h). A structure
    /// that reports its steps sets recorder.detailed; the default only fills the totals.
    virtual Hit intersect(const Ray& ray, TraversalRecorder& recorder) const;
    /// Any hit, recording the traversal as intersect() above does (detailed for bvh, grid, tetra).
    virtual bool occluded(const Ray& ray, TraversalRecorder& recorder) const;
    /// Calls `visit` for every node, non-empty cell or tetrahedron the structure draws, parents
    /// before children, in the numbering recorded steps use, and returns true; returns false,
    /// visiting nothing, for a structure that does not draw itself (brute force, instances).
    virtual bool for_each_node(const DrawnNodeVisitor& visit) const;
    /// What for_each_node's shapes and depths mean; empty when it draws nothing.
    virtual std::optional<DrawingLegend> drawing_legend() const;

    /// Closest hit of every ray: hits[i] is what intersect(rays[i]) returns, on options.threads
    /// threads. Throws Error if the spans differ in size.
    void intersect(std::span<const Ray> rays, std::span<Hit> hits, const BatchOptions& options = {}) const;
    /// Any hit of every ray: occluded[i] is 1 if occluded(rays[i]), else 0.
    void occluded(std::span<const Ray> rays, std::span<uint8_t> occluded, const BatchOptions& options = {}) const;

    /// Every surface crossing within [ray.tmin, ray.tmax], sorted by t, appended to `out`. Hits
    /// within kSameCrossing relative t of the last crossing kept are the same crossing (a shared
    /// edge or vertex) and are left out, so parity tells inside from outside. The default asks
    /// intersect() again from just past each crossing; brute force enumerates every primitive.
    virtual void all_hits(const Ray& ray, std::vector<Hit>& out) const;
    /// The number of crossings all_hits() lists.
    virtual uint32_t count_hits(const Ray& ray) const;
    /// The closest point of the surface to `p`. The default throws Error: it needs the primitives'
    /// geometry, which brute force and the BVH (`bvh`) answer for triangle scenes.
    virtual NearestPoint closest_point(const Vec3& p) const;
    /// Whether closest_point() answers for this structure and scene.
    virtual bool has_closest_point() const { return false; }

    /// Batch forms of the three, on options.threads threads (options.coherent is refused: Error).
    void count_hits(std::span<const Ray> rays, std::span<uint32_t> counts, const BatchOptions& options = {}) const;
    HitLists all_hits(std::span<const Ray> rays, const BatchOptions& options = {}) const;
    void closest_points(std::span<const Vec3> points, std::span<NearestPoint> out, const BatchOptions& options = {}) const;

    /// Writes the structure's payload (save_accel() adds the checked header); throws Error if
    /// the structure cannot be saved.
    virtual void save(std::ostream& out) const;

    /// Brings the structure up to date with `scene` after its vertices moved (Scene::set_vertices)
    /// with the same topology: the scene must be the one the structure was built over, with the
    /// same primitives in the same id order; only positions may differ. The tree keeps its shape
    /// and its boxes are recomputed, so queries answer exactly as brute force on the moved scene
    /// but may be slower than after a rebuild (README, "Moving vertices: refit": when to rebuild).
    /// Not while queries run on the structure (as a rebuild would not be). Structures that
    /// cannot refit (refittable() false) throw Error naming the structure and saying to rebuild;
    /// a wrong primitive count is refused with Error. On Error the structure is unchanged.
    /// Runs on up to `threads` threads (0: all cores).
    virtual void refit(const Scene& scene, unsigned threads = 0);
    /// Whether refit() is supported by this structure (bvh, bvh8, obb).
    virtual bool refittable() const { return false; }

    /// Whether the structure was built with `precision=double` (brute, bvh): vertices, boxes and
    /// ray arithmetic in double. Such a structure answers float rays too (widened exactly, the hit
    /// rounded back to float); the double entry points below are where its precision shows.
    virtual bool double_precision() const { return false; }
    /// Closest hit of a double-precision ray within [ray.tmin, ray.tmax]. Answered by structures
    /// with double_precision() only: the others throw Error naming the spec and saying to build
    /// with `precision=double` (a float structure would round the ray and lose what it is for).
    /// The ray must be meaningful (make_ray()).
    virtual HitD intersect_double(const RayD& ray) const;
    /// Is anything hit within [ray.tmin, ray.tmax]? Same contract as intersect_double().
    virtual bool occluded_double(const RayD& ray) const;
    /// Batch forms on options.threads threads: hits[i] is intersect_double(rays[i]), occluded[i]
    /// 1 if occluded_double(rays[i]). Throws Error if the spans differ in size, or before tracing
    /// anything if the structure is not double_precision().
    void intersect_double(std::span<const RayD> rays, std::span<HitD> hits, const BatchOptions& options = {}) const;
    void occluded_double(std::span<const RayD> rays, std::span<uint8_t> occluded, const BatchOptions& options = {}) const;

    /// Canonical spec string and build time, set by build_accel()/load_accel().
    const std::string& spec() const { return spec_; }
    double build_ms() const { return build_ms_; }
    void set_origin(std::string spec, double build_ms) {
        spec_ = std::move(spec);
        build_ms_ = build_ms;
    }

    /// One thread's share of a batch (at most kBatchGrain rays), answered on the calling thread:
    /// the batch functions split the rays and call these, and so do the row readers
    /// (query/ray_rows.h), whose threads convert and answer a chunk each. The default asks
    /// intersect()/occluded() ray by ray; a structure overrides them to trace groups of rays
    /// together, with the same answers.
    virtual void intersect_chunk(std::span<const Ray> rays, std::span<Hit> hits, bool coherent) const;
    virtual void occluded_chunk(std::span<const Ray> rays, std::span<uint8_t> occluded) const;

protected:

    /// Stats with the fields every structure shares already filled in.
    AccelStats base_stats() const {
        AccelStats s;
        s.spec = spec_;
        s.build_ms = build_ms_;
        return s;
    }
    /// base_stats() plus a tree's figures (nodes, leaves, depth, SAH cost) and the sizes.
    AccelStats tree_stats(const TreeFigures& f, size_t primitives, size_t bytes, size_t primitive_bytes) const {
        AccelStats s = base_stats();
        s.primitives = primitives;
        s.nodes = f.nodes;
        s.leaves = f.leaves;
        s.max_depth = f.max_depth;
        s.bytes = bytes;
        s.primitive_bytes = primitive_bytes;
        s.sah_cost = f.sah_cost;
        return s;
    }

private:
    std::string spec_;
    double build_ms_ = 0.0;
};

/// Implements Accel's virtual entry points for a structure with two templates:
///   template <class C> Hit closest(const Ray&, C& counters) const;
///   template <class C> bool any(const Ray&, C& counters) const;
/// where C is RayCounters or NoCounters (free when not counting). A structure that traces in
/// double (`precision=double`) says so with kDoublePrecision = true and takes RayD, answering
/// HitD: float rays are widened to double and their hits rounded back, double rays answered as
/// they are. A structure keeping the two private befriends AccelBase.
template <class Derived>
class AccelBase : public Accel {
public:
    using Accel::intersect;  // the batch overloads stay visible next to the per-ray ones
    using Accel::intersect_double;
    using Accel::occluded;
    using Accel::occluded_double;
    Hit intersect(const Ray& ray) const final {
        NoCounters none;
        return closest_of(ray, none);
    }
    Hit intersect(const Ray& ray, RayCounters& counters) const final { return closest_of(ray, counters); }
    bool occluded(const Ray& ray) const final {
        NoCounters none;
        return any_of(ray, none);
    }
    bool occluded(const Ray& ray, RayCounters& counters) const final { return any_of(ray, counters); }
    /// Structures whose traversal calls the record_* members say so with kRecordsSteps = true;
    /// a double structure keeps Accel's counting default.
    Hit intersect(const Ray& ray, TraversalRecorder& recorder) const final {
        if constexpr (in_double()) {
            return Accel::intersect(ray, recorder);
        } else {
            if constexpr (requires { Derived::kRecordsSteps; }) recorder.detailed = Derived::kRecordsSteps;
            return self().closest(ray, recorder);
        }
    }
    /// Structures whose any-hit walk calls them say so with kRecordsAnyHitSteps = true; the others
    /// keep Accel's counting default (their any() is not instantiated for a recorder).
    bool occluded(const Ray& ray, TraversalRecorder& recorder) const final {
        if constexpr (!in_double() && requires { Derived::kRecordsAnyHitSteps; }) {
            recorder.detailed = Derived::kRecordsAnyHitSteps;
            return self().any(ray, recorder);
        } else {
            return Accel::occluded(ray, recorder);
        }
    }

    bool double_precision() const final { return in_double(); }
    HitD intersect_double(const RayD& ray) const final {
        if constexpr (in_double()) {
            NoCounters none;
            return self().closest(ray, none);
        } else {
            return Accel::intersect_double(ray);  // refused: the structure is float
        }
    }
    bool occluded_double(const RayD& ray) const final {
        if constexpr (in_double()) {
            NoCounters none;
            return self().any(ray, none);
        } else {
            return Accel::occluded_double(ray);
        }
    }

    /// A structure draws itself when its folder's draw.h declares draw_nodes and draw_legend
    /// for the type its data() returns (found by argument-dependent lookup); bvh8 overrides.
    bool for_each_node(const DrawnNodeVisitor& visit) const override {
        if constexpr (requires { draw_nodes(self().data(), visit); }) {
            draw_nodes(self().data(), visit);
            return true;
        } else {
            return Accel::for_each_node(visit);
        }
    }
    std::optional<DrawingLegend> drawing_legend() const override {
        if constexpr (requires { draw_legend(self().data()); })
            return draw_legend(self().data());
        else
            return Accel::drawing_legend();
    }

private:
    /// Whether Derived traces in double (its kDoublePrecision). A function, not a constant: it is
    /// read in the members' bodies, where Derived is complete.
    static constexpr bool in_double() {
        if constexpr (requires { Derived::kDoublePrecision; })
            return Derived::kDoublePrecision;
        else
            return false;
    }

    const Derived& self() const { return static_cast<const Derived&>(*this); }
    template <class C>
    Hit closest_of(const Ray& ray, C& counters) const {
        if constexpr (in_double())
            return to_hit(self().closest(to_double(ray), counters));
        else
            return self().closest(ray, counters);
    }
    template <class C>
    bool any_of(const Ray& ray, C& counters) const {
        if constexpr (in_double())
            return self().any(to_double(ray), counters);
        else
            return self().any(ray, counters);
    }
};

}  // namespace thicket
