#pragma once
/// Recording one ray's traversal step by step (what `thicket explain` prints and `thicket
/// explore` replays). A traversal takes a counting policy C (RayCounters, NoCounters: core/ray.h);
/// a policy that also has the record_* members below is told, in order, each node or cell whose
/// box was tested (with its entry distance, or culled) and each primitive tested. Structures ask
/// `RecordsSteps<C>` with `if constexpr`, so the counting and non-counting paths compile exactly
/// as before: recording costs nothing when unused.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "thicket/core/aabb.h"
#include "thicket/core/ray.h"

namespace thicket {

/// One step of a recorded traversal.
struct TraversalStep {
    enum class Kind : uint8_t {
        Enter,  ///< a node's box (or a cell) the ray enters at `t`, within the query's interval
        Cull,   ///< a node whose box was tested and missed (or lies beyond the current hit): t is +inf
        Prim,   ///< a primitive tested: `id` is the primitive id, t is the closest hit after the test
        Skip,   ///< a node entered at t earlier, dropped unvisited: the hit found since is nearer
    };
    Kind kind;
    uint32_t id;  ///< node or cell id in the structure's own numbering (Accel::for_each_node), or primitive id
    float t;
};

/// The recording policy. node()/prim() count as RayCounters does (so the totals agree with
/// `thicket bench`'s figures); the record_* members keep the first `limit` steps in order and
/// count the rest in `dropped`.
struct TraversalRecorder {
    uint64_t nodes = 0;
    uint64_t prims = 0;
    std::vector<TraversalStep> steps;
    size_t limit = 100000;
    uint64_t dropped = 0;
    /// Set by the structure: true when it reports steps, false when only the totals are known.
    bool detailed = false;

    void node() { ++nodes; }
    void prim() { ++prims; }
    /// A node or cell tested: entered at t_enter, or culled when t_enter is +inf.
    void record_node(uint32_t id, float t_enter) {
        add({t_enter == kInfinity ? TraversalStep::Kind::Cull : TraversalStep::Kind::Enter, id, t_enter});
    }
    /// Node `id`, entered at t_enter and deferred, is dropped: a hit nearer than t_enter was found since.
    void record_skip(uint32_t id, float t_enter) { add({TraversalStep::Kind::Skip, id, t_enter}); }
    /// Primitive `id` was tested; `closest` is the closest hit distance after the test.
    void record_prim(uint32_t id, float closest) { add({TraversalStep::Kind::Prim, id, closest}); }

private:
    void add(const TraversalStep& s) {
        if (steps.size() < limit)
            steps.push_back(s);
        else
            ++dropped;
    }
};

/// Whether a counting policy wants the steps (TraversalRecorder does, RayCounters and NoCounters not).
template <class C>
concept RecordsSteps = requires(C& c, uint32_t id, float t) {
    c.record_node(id, t);
    c.record_prim(id, t);
};

}  // namespace thicket
