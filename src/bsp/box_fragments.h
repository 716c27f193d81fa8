#pragma once
// Fragments of primitives that are not triangles: boxes (the part of the primitive's bounds in
// the cell, tightened by the set's clipped_bounds hook), split by axis-aligned planes taken from
// those boxes. The BSP then behaves as a kD-tree with bounds-based assignment.
#include <span>
#include <vector>

#include "fragments.h"
#include "thicket/bsp/build.h"

namespace thicket::bsp_build {

class BoxFragments {
public:
    static constexpr bool kPolygons = false;

    struct Frag {
        uint32_t prim;
        Aabb box;
    };
    struct Set {
        std::vector<Frag> frags;
        size_t size() const { return frags.size(); }
    };

    BoxFragments(std::span<const Aabb> bounds, const BspClip& clip) : bounds_(bounds), clip_(clip) {}

    /// Every primitive with its bounds (primitives with empty bounds cannot be hit: left out).
    Set initial() const {
        Set s;
        for (uint32_t i = 0; i < bounds_.size(); ++i)
            if (!bounds_[i].empty()) s.frags.push_back({i, bounds_[i]});
        return s;
    }

    uint32_t prim(const Set& s, size_t i) const { return s.frags[i].prim; }

    /// The points whose distances to an axis-aligned plane decide placement: the box's corners
    /// of least and greatest coordinates.
    void gather(const Set& s, size_t i, std::vector<P3>& out) const {
        out.push_back(to_p3(s.frags[i].box.min));
        out.push_back(to_p3(s.frags[i].box.max));
    }
    double tolerance() const { return 0.0; }
    Aabb bounds(const Set& s, size_t i) const { return s.frags[i].box; }

    /// The six faces of fragment i's box, those strictly inside the cell.
    template <class Out>
    void candidates(const Set& s, size_t i, const Aabb& cell, Out& out) const {
        const Aabb& b = s.frags[i].box;
        for (int a = 0; a < 3; ++a)
            for (float v : {b.min[a], b.max[a]})
                if (v > cell.min[a] && v < cell.max[a]) {
                    BspPlane p;
                    p.normal[a] = 1.0f;
                    p.offset = v;
                    out.push_back(p);
                }
    }

    /// No second choice: the box faces already separate whatever can be separated.
    template <class Out>
    void edge_candidates(const Set&, size_t, const Aabb&, Out&) const {}

    /// Exact in float: a box touching the plane from one side stays on that side; a box flat in
    /// the plane goes to the front.
    Placement place(const Set& s, size_t i, const BspPlane& plane) const {
        const int a = axis(plane);
        const Aabb& b = s.frags[i].box;
        if (b.min[a] == plane.offset && b.max[a] == plane.offset) return {Side::Front, true};
        if (b.max[a] <= plane.offset) return {Side::Back, false};
        if (b.min[a] >= plane.offset) return {Side::Front, false};
        return {Side::Straddle, false};
    }

    /// A straddling box is cut at the plane and each half tightened by the clip hook; a half the
    /// primitive does not reach is dropped.
    void send(const Set& from, size_t i, const BspPlane& plane, Placement where, Set& back, Set& front) const {
        const Frag& fr = from.frags[i];
        if (where.side == Side::Back) {
            back.frags.push_back(fr);
        } else if (where.side == Side::Front) {
            front.frags.push_back(fr);
        } else {
            const int a = axis(plane);
            Aabb lo = fr.box, hi = fr.box;
            lo.max[a] = plane.offset;
            hi.min[a] = plane.offset;
            lo = clip_(fr.prim, lo);
            hi = clip_(fr.prim, hi);
            if (!lo.empty()) back.frags.push_back({fr.prim, lo});
            if (!hi.empty()) front.frags.push_back({fr.prim, hi});
        }
    }

    bool is_piece(const Set&, size_t) const { return false; }
    double area(const Set&, size_t) const { return 0.0; }
    double prim_area(uint32_t) const { return 0.0; }
    void polygon(const Set&, size_t, std::vector<P3>& out) const { out.clear(); }

private:
    static int axis(const BspPlane& p) { return p.normal.x != 0.0f ? 0 : (p.normal.y != 0.0f ? 1 : 2); }

    std::span<const Aabb> bounds_;
    const BspClip& clip_;
};

}  // namespace thicket::bsp_build
