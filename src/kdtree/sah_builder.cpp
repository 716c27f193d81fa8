// The O(N log N) SAH kD-tree builder of Wald & Havran 2006 ("On building fast kd-trees for ray
// tracing, and on doing that in O(N log N)"). Every primitive contributes, per axis, a start and
// an end event at its clipped bounds (or one planar event when flat on that axis). The events
// are sorted once, at the root. A node finds its best plane by one linear sweep per axis; its
// children's event lists are made without sorting again: events of primitives wholly on one
// side are spliced out in order, the few primitives straddling the plane are clipped to each
// child voxel ("perfect splits") and their new events, sorted among themselves, are merged in.
#include <algorithm>
#include <array>
#include <vector>

#include "builder.h"
#include "thicket/core/ray.h"

namespace thicket::kd_build {
namespace {

enum EventType : uint32_t { kEnd = 0, kPlanar = 1, kStart = 2 };

/// One event: a position and (type << 30 | primitive). Ordered by position, then type (ends
/// before planars before starts, as the sweep needs), then primitive: a total order, so the
/// build does not depend on the sort's treatment of ties.
struct Event {
    float pos;
    uint32_t key;

    uint32_t prim() const { return key & kKdMaxField; }
    uint32_t type() const { return key >> 30; }
    bool operator<(const Event& o) const { return pos < o.pos || (pos == o.pos && key < o.key); }
};

using Events = std::array<std::vector<Event>, 3>;

void add_events(Events& ev, uint32_t prim, const Aabb& b) {
    for (int k = 0; k < 3; ++k) {
        if (b.min[k] == b.max[k]) {
            ev[k].push_back({b.min[k], (kPlanar << 30) | prim});
        } else {
            ev[k].push_back({b.min[k], (kStart << 30) | prim});
            ev[k].push_back({b.max[k], (kEnd << 30) | prim});
        }
    }
}

struct Plane {
    int axis = -1;
    float pos = 0.0f;
    bool planar_left = true;
    float cost = kInfinity;
};

enum Side : uint8_t { kBoth, kLeft, kRight };

class SahBuilder {
public:
    SahBuilder(const KdBuildInput& input, const KdCostModel& cost, uint32_t max_depth, TreeWriter& out)
        : input_(input), cost_(cost), max_depth_(max_depth), out_(out), side_(input.bounds.size(), kBoth) {}

    void build(std::span<const uint32_t> prims, const Aabb& root) {
        Events ev;
        for (auto& e : ev) e.reserve(2 * prims.size());
        for (uint32_t p : prims) add_events(ev, p, input_.bounds[p]);
        for (auto& e : ev) std::sort(e.begin(), e.end());
        // Depth first with an explicit stack (left child first, as the tree is written), so the
        // depth costs heap, not C stack.
        std::vector<Task> stack;
        stack.push_back({std::move(ev), root, uint32_t(prims.size()), 0, kNoAbove});
        while (!stack.empty()) {
            Task task = std::move(stack.back());
            stack.pop_back();
            if (task.above != kNoAbove) out_.start_above(task.above);
            node(std::move(task), stack);
        }
    }

private:
    static constexpr uint32_t kNoAbove = ~0u;
    /// A subtree still to build: `voxel` holding `count` primitives whose events are `ev`; its
    /// parent is `above` when it is a right child (the writer must be told before it starts).
    struct Task {
        Events ev;
        Aabb voxel;
        uint32_t count, depth, above;
    };

    /// Writes task's node: a leaf, or an interior node whose children's tasks it pushes.
    void node(Task task, std::vector<Task>& stack) {
        Events& ev = task.ev;
        const Aabb& voxel = task.voxel;
        const uint32_t count = task.count, depth = task.depth;
        Plane plane;
        if (count > 0 && depth < max_depth_) plane = find_plane(ev, voxel, count);
        if (plane.axis < 0 || !(plane.cost < kd_leaf_cost(cost_, count))) {
            make_leaf(ev[0]);
            return;
        }
        Aabb left_voxel = voxel, right_voxel = voxel;
        left_voxel.max[plane.axis] = plane.pos;
        right_voxel.min[plane.axis] = plane.pos;

        Events left, right;
        uint32_t left_count = 0, right_count = 0;
        split_events(ev, plane, left_voxel, right_voxel, left, right, left_count, right_count);

        const uint32_t me = out_.interior(plane.axis, plane.pos);
        Events().swap(ev);  // free the parent's events before descending
        stack.push_back({std::move(right), right_voxel, right_count, depth + 1, me});
        stack.push_back({std::move(left), left_voxel, left_count, depth + 1, kNoAbove});
    }

    /// The sweep: per axis, visit the distinct event positions in order with the counts of
    /// primitives reaching below (nl), lying in (np) and reaching above (nr) each plane.
    Plane find_plane(const Events& ev, const Aabb& voxel, uint32_t count) const {
        Plane best;
        for (int axis = 0; axis < 3; ++axis) {
            const std::vector<Event>& e = ev[axis];
            const KdPlanePricer pricer(cost_, voxel, axis);
            uint32_t nl = 0, nr = count;
            for (size_t i = 0, n = e.size(); i < n;) {
                const float pos = e[i].pos;
                uint32_t at[3] = {0, 0, 0};  // ends, planars, starts at pos
                do ++at[e[i++].type()];
                while (i < n && e[i].pos == pos);
                nr -= at[kPlanar] + at[kEnd];
                KdPlaneCost c;
                if (pricer.price(pos, nl, at[kPlanar], nr, c) && c.cost < best.cost)
                    best = {axis, pos, c.planar_left, c.cost};
                nl += at[kStart] + at[kPlanar];
            }
        }
        return best;
    }

    /// Classify, splice, clip and merge: the children's sorted event lists in linear time plus
    /// the sorting of the straddling primitives' new events.
    void split_events(Events& ev, const Plane& plane, const Aabb& left_voxel, const Aabb& right_voxel, Events& left,
                      Events& right, uint32_t& left_count, uint32_t& right_count) {
        // Classify by the events on the split axis; a start decides "right only" or "both", the
        // matching end (which comes later) may turn "both" into "left only".
        // Counted as they are decided: a start of "both" is counted when its end settles it.
        straddling_.clear();
        for (const Event& e : ev[plane.axis]) {
            const uint32_t p = e.prim();
            if (e.type() == kStart) {
                side_[p] = e.pos >= plane.pos ? kRight : kBoth;
                right_count += e.pos >= plane.pos;
            } else if (e.type() == kEnd) {
                if (side_[p] != kBoth) continue;
                if (e.pos <= plane.pos) {
                    side_[p] = kLeft;
                    ++left_count;
                } else {
                    straddling_.push_back(p);
                }
            } else {
                const bool left = e.pos < plane.pos || (e.pos == plane.pos && plane.planar_left);
                side_[p] = left ? kLeft : kRight;
                ++(left ? left_count : right_count);
            }
        }
        // Splice: events of one-sided primitives keep their order. At most two events per
        // primitive and axis: reserving exactly that keeps the lists of waiting nodes small.
        for (int k = 0; k < 3; ++k) {
            left[k].reserve(2 * size_t(left_count));
            right[k].reserve(2 * size_t(right_count));
            for (const Event& e : ev[k]) {
                const Side s = Side(side_[e.prim()]);
                if (s == kLeft)
                    left[k].push_back(e);
                else if (s == kRight)
                    right[k].push_back(e);
            }
            std::vector<Event>().swap(ev[k]);  // the parent's events are no longer needed
        }
        if (straddling_.empty()) return;
        // Perfect splits: clip each straddling primitive to both child voxels.
        Events new_left, new_right;
        for (uint32_t p : straddling_) {
            const Aabb lb = input_.clip(p, left_voxel), rb = input_.clip(p, right_voxel);
            if (!lb.empty()) {
                add_events(new_left, p, lb);
                ++left_count;
            }
            if (!rb.empty()) {
                add_events(new_right, p, rb);
                ++right_count;
            }
        }
        for (int k = 0; k < 3; ++k) {
            merge_into(left[k], new_left[k]);
            merge_into(right[k], new_right[k]);
        }
    }

    /// Sorts `extra` and merges it into the sorted `list` (into a new array of the exact size).
    static void merge_into(std::vector<Event>& list, std::vector<Event>& extra) {
        if (extra.empty()) return;
        std::sort(extra.begin(), extra.end());
        std::vector<Event> merged(list.size() + extra.size());
        std::merge(list.begin(), list.end(), extra.begin(), extra.end(), merged.begin());
        list.swap(merged);
    }

    /// A leaf references each primitive once: at its start or planar event on axis 0.
    void make_leaf(const std::vector<Event>& axis0) {
        leaf_.clear();
        for (const Event& e : axis0)
            if (e.type() != kEnd) leaf_.push_back(e.prim());
        out_.leaf(leaf_);
    }

    const KdBuildInput& input_;
    const KdCostModel cost_;
    const uint32_t max_depth_;
    TreeWriter& out_;
    std::vector<uint8_t> side_;
    std::vector<uint32_t> straddling_, leaf_;
};

}  // namespace

void build_sah(const KdBuildInput& input, const KdCostModel& cost, uint32_t max_depth, std::span<const uint32_t> prims,
               const Aabb& root, TreeWriter& out) {
    SahBuilder(input, cost, max_depth, out).build(prims, root);
}

}  // namespace thicket::kd_build
