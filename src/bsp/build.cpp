// The BSP builder's skeleton, shared by triangle polygons and boxes: sample candidate planes,
// score them on a sample of the node's fragments, partition (cutting straddlers), recurse; with
// the depth cap and the fragment budget that keep the tree from blowing up.
#include "thicket/bsp/build.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "box_fragments.h"
#include "polygon_fragments.h"
#include "thicket/core/error.h"
#include "thicket/core/ray_box.h"

namespace thicket {
namespace bsp_build {
namespace {

/// Fragments each candidate plane is scored on: a node's own when it has at most
/// kScoreSampleMin, else an evenly spaced sample of 1/kScoreShare of them within
/// [kScoreSampleMin, kScoreSampleMax]. The top of the tree, which decides most of its quality,
/// is scored on the largest samples; below, small samples choose about as well.
constexpr size_t kScoreSampleMin = 64, kScoreSampleMax = 512, kScoreShare = 16;
/// Small nodes try fewer planes: at most a quarter of their fragments' planes, at least this many.
constexpr size_t kSmallNodeCandidates = 4;
/// Candidates partitioned in full before a node gives up and becomes a leaf (a sampled score can
/// promise a separation or a fragment count that the whole node does not deliver).
constexpr int kPartitionTries = 4;
/// Share of a node's fragments on one side beyond which the autopartition candidates count as
/// peeling, and the axis fallback's planes are scored too.
constexpr double kFallbackShare = 0.875;
/// The balance score's weight of one straddling fragment against one fragment of imbalance.
constexpr double kBalanceSplitWeight = 8.0;

void check_options(const BspBuildOptions& o) {
    auto in = [](int v, int lo, int hi) { return v >= lo && v <= hi; };
    if (!in(o.candidates, 1, 1024)) throw Error("bsp: candidates=" + std::to_string(o.candidates) + " must be in [1, 1024]");
    if (!in(o.max_leaf, 1, 1 << 20)) throw Error("bsp: max-leaf=" + std::to_string(o.max_leaf) + " must be positive");
    if (!in(o.max_depth, 0, int(kBspMaxDepth)))
        throw Error("bsp: max-depth=" + std::to_string(o.max_depth) + " must be in [0, " + std::to_string(kBspMaxDepth) + "]");
    if (!in(o.fragment_budget, 1, 1024))
        throw Error("bsp: fragment-budget=" + std::to_string(o.fragment_budget) + " must be in [1, 1024]");
}

float scale_of(const Aabb& b) {
    return b.empty() ? 0.0f : max_component(max(abs(b.min), abs(b.max)));
}

template <class Frags>
class Builder {
    using Set = typename Frags::Set;

public:
    Builder(const Frags& frags, const BspBuildOptions& options, size_t prim_count, BspData& out,
            std::vector<BspFragment>* keep)
        : frags_(frags), options_(options), out_(out), keep_(keep), pieces_(prim_count, 0), scale_(out.scale) {}

    void run(Set root, uint64_t budget) {
        out_.splinters.polygons = Frags::kPolygons;
        if (root.size() == 0) {
            // Nothing that can be hit: one empty leaf keeps traversal uniform.
            out_.nodes.emplace_back();
            out_.nodes[0].count = BspNode::kLeafBit;
            return;
        }
        out_.nodes.emplace_back();
        // Depth first with an explicit stack (back before front, the order nodes and leaves are
        // written in), so the depth costs heap, not C stack.
        std::vector<Task> stack;
        stack.push_back({0, std::move(root), out_.bounds, 0, budget});
        while (!stack.empty()) {
            Task task = std::move(stack.back());
            stack.pop_back();
            build(task.node, std::move(task.set), task.cell, task.depth, task.budget, stack);
        }
        for (uint32_t p : pieces_) out_.splinters.split_triangles += p > 1 ? 1 : 0;
        out_.splinters.fragments = out_.refs.size();
        if (out_.refs.size() >= (uint64_t(1) << 31)) throw Error("bsp: more than 2^31 fragments");
    }

private:
    struct Candidate {
        BspPlane plane;
        double cost;
        uint64_t total;   ///< estimated fragments after the split
        double largest;   ///< estimated share of the node's fragments on the fuller side
        uint32_t order;   ///< position among the node's proposals
    };

    /// The fragments candidates are scored on (all of a small node's, an evenly spaced sample
    /// of a large one's), their placement points gathered once, in float and one array per
    /// coordinate so that each candidate's distances are one vectorized loop.
    struct Sample {
        std::vector<uint32_t> index, start;
        std::vector<float> x, y, z, dist;
        std::vector<Aabb> boxes;
        size_t size() const { return index.size(); }
    };

    /// Fills the scratch sample for `set` (the scratch keeps its capacity from node to node).
    Sample& take_sample(const Set& set) const {
        const size_t n = set.size();
        const size_t m = std::min(n, std::clamp(n / kScoreShare, kScoreSampleMin, kScoreSampleMax));
        Sample& s = sample_;
        s.index.resize(m);
        s.start.assign(m + 1, 0);
        s.boxes.resize(m);
        std::vector<P3>& points = points_;
        points.clear();
        for (size_t i = 0; i < m; ++i) {
            s.index[i] = uint32_t(i * n / m);
            const size_t first = points.size();
            frags_.gather(set, s.index[i], points);
            s.start[i + 1] = uint32_t(points.size());
            s.boxes[i] = points_box(points.data() + first, points.size() - first);
        }
        s.x.resize(points.size());
        s.y.resize(points.size());
        s.z.resize(points.size());
        s.dist.resize(points.size());
        for (size_t j = 0; j < points.size(); ++j) {
            s.x[j] = float(points[j][0]);
            s.y[j] = float(points[j][1]);
            s.z[j] = float(points[j][2]);
        }
        return s;
    }

    enum class Source { Own, Edges, Axis };

    /// Candidate planes: those of `candidates` fragments evenly spaced over the node (their
    /// triangles' planes, or those triangles' edge planes), or the axis-aligned planes through
    /// the median of the sample's box centres.
    std::vector<BspPlane> propose(const Set& set, const Aabb& cell, const Sample& sample, Source source) const {
        std::vector<BspPlane> planes;
        const size_t n = set.size();
        const size_t k = std::min({n, size_t(options_.candidates), std::max(kSmallNodeCandidates, n / 4)});
        if (source == Source::Axis) {
            std::vector<float> centre(sample.size());
            for (int a = 0; a < 3; ++a) {
                for (size_t i = 0; i < sample.size(); ++i) centre[i] = sample.boxes[i].center()[a];
                std::nth_element(centre.begin(), centre.begin() + centre.size() / 2, centre.end());
                BspPlane p;
                p.normal[a] = 1.0f;
                p.offset = centre[centre.size() / 2];
                if (p.offset > cell.min[a] && p.offset < cell.max[a]) planes.push_back(p);
            }
            return planes;
        }
        for (size_t j = 0; j < k; ++j) {
            const size_t i = (2 * j + 1) * n / (2 * k);
            if (source == Source::Edges)
                frags_.edge_candidates(set, i, cell, planes);
            else
                frags_.candidates(set, i, cell, planes);
        }
        return planes;
    }

    /// Scores planes on the sample and appends the useful ones to `ranked`: those that leave
    /// fragments on both sides and at least one fragment wholly on a side.
    void score(const Set& set, const Aabb& cell, Sample& sample, const std::vector<BspPlane>& planes,
               std::vector<Candidate>& ranked) const {
        const size_t n = set.size(), m = sample.size(), points = sample.x.size();
        // Float distances are estimates: a fragment within a few ulps of the plane may be scored
        // as straddling; the partition itself classifies in double.
        const float tolerance = float(frags_.tolerance()) + 4.0f * rounding_gamma(4) * scale_;
        for (size_t c = 0; c < planes.size(); ++c) {
            const BspPlane& p = planes[c];
            bool seen = false;
            for (size_t e = 0; e < c; ++e) seen |= planes[e].normal == p.normal && planes[e].offset == p.offset;
            if (seen) continue;
            const float nx = p.normal.x, ny = p.normal.y, nz = p.normal.z, off = p.offset;
            float* const dist = sample.dist.data();
            const float *px = sample.x.data(), *py = sample.y.data(), *pz = sample.z.data();
            for (size_t j = 0; j < points; ++j) dist[j] = nx * px[j] + ny * py[j] + nz * pz[j] - off;
            size_t nb = 0, nf = 0, ns = 0;
            Aabb bb, bf;
            for (size_t i = 0; i < m; ++i) {
                float lo = dist[sample.start[i]], hi = lo;
                for (uint32_t j = sample.start[i] + 1; j < sample.start[i + 1]; ++j) {
                    lo = std::min(lo, dist[j]);
                    hi = std::max(hi, dist[j]);
                }
                const bool back_reached = lo < -tolerance, front_reached = hi > tolerance;
                const Side side = back_reached && front_reached ? Side::Straddle
                                  : front_reached               ? Side::Front
                                  : back_reached                ? Side::Back
                                               : frags_.place(set, sample.index[i], p).side;  // in the plane
                if (side != Side::Front) bb.grow(sample.boxes[i]);
                if (side != Side::Back) bf.grow(sample.boxes[i]);
                (side == Side::Back ? nb : side == Side::Front ? nf : ns)++;
            }
            const size_t back = nb + ns, front = nf + ns;
            if (back == 0 || front == 0 || nb + nf == 0) continue;
            double cost;
            if (options_.cost == BspCost::Sah) {
                Aabb cb, cf;
                bsp_cut_box(cell, p, cb, cf);
                const double ab = intersection(cb, bb).half_area();
                const double af = intersection(cf, bf).half_area();
                cost = ab * double(back) + af * double(front);
            } else {
                cost = std::fabs(double(front) - double(back)) + kBalanceSplitWeight * double(ns);
            }
            ranked.push_back({p, cost, uint64_t(n) + uint64_t(double(ns) * double(n) / double(m)),
                              double(std::max(back, front)) / double(m), uint32_t(ranked.size())});
        }
    }

    /// The useful candidates, best first: the node's own triangles' planes; their edge planes
    /// when none of those separates anything; and, with the axis fallback, when the best of
    /// them still leaves more than kFallbackShare of the fragments on one side (autopartition
    /// peels curved surfaces one tangent plane at a time), axis-aligned median planes as well.
    std::vector<Candidate> rank(const Set& set, const Aabb& cell) const {
        Sample& sample = take_sample(set);
        std::vector<Candidate> ranked;
        score(set, cell, sample, propose(set, cell, sample, Source::Own), ranked);
        if (ranked.empty()) score(set, cell, sample, propose(set, cell, sample, Source::Edges), ranked);
        // Ties keep proposal order, so the tree does not depend on the library's sort.
        auto better = [](const Candidate& a, const Candidate& b) {
            return a.cost < b.cost || (a.cost == b.cost && a.order < b.order);
        };
        std::sort(ranked.begin(), ranked.end(), better);
        if (options_.axis_fallback && set.size() > size_t(4 * options_.max_leaf) &&
            (ranked.empty() || ranked.front().largest > kFallbackShare)) {
            score(set, cell, sample, propose(set, cell, sample, Source::Axis), ranked);
            std::sort(ranked.begin(), ranked.end(), better);
        }
        return ranked;
    }

    /// A node still to build: its fragments, cell, depth and fragment budget.
    struct Task {
        uint32_t node;
        Set set;
        Aabb cell;
        uint32_t depth;
        uint64_t budget;
    };

    /// Makes `node` a leaf, or an interior node whose children's tasks it pushes (back on top).
    void build(uint32_t node, Set set, const Aabb& cell, uint32_t depth, uint64_t budget, std::vector<Task>& stack) {
        const size_t n = set.size();
        if (n <= size_t(options_.max_leaf)) return make_leaf(node, set);
        if (depth >= uint32_t(options_.max_depth)) {
            ++out_.splinters.depth_capped;
            return make_leaf(node, set);
        }
        const std::vector<Candidate> ranked = rank(set, cell);
        bool over_budget = false;
        int tries = 0;
        for (const Candidate& c : ranked) {
            if (tries == kPartitionTries) break;
            if (c.total > budget) {
                over_budget = true;
                continue;
            }
            ++tries;
            Set back, front;
            back.frags.reserve(n / 2 + 8);
            front.frags.reserve(n / 2 + 8);
            uint64_t splits = 0, dropped = 0, in_plane = 0;
            for (size_t i = 0; i < n; ++i) {
                const Placement where = frags_.place(set, i, c.plane);
                const size_t before = back.size() + front.size();
                frags_.send(set, i, c.plane, where, back, front);
                const size_t made = back.size() + front.size() - before;
                if (where.side == Side::Straddle) {
                    ++splits;
                    dropped += 2 - made;
                }
                in_plane += where.in_plane ? 1 : 0;
            }
            if (back.size() == 0 || front.size() == 0) continue;
            const uint64_t total = back.size() + front.size();
            if (total > budget) {
                over_budget = true;
                continue;
            }
            out_.splinters.splits += splits;
            out_.splinters.dropped += dropped;
            out_.splinters.in_plane += in_plane;
            const auto child = uint32_t(out_.nodes.size());
            out_.nodes.resize(out_.nodes.size() + 2);
            out_.nodes[node].plane = c.plane;
            out_.nodes[node].index = child;
            out_.nodes[node].count = 0;
            // The budget is shared in proportion to the fragments each side receives, so neither
            // side can starve the other, and both fit (budget >= total). In double: the product
            // could overflow 64 bits; the clamp keeps each side's share at least its fragments.
            const auto share = uint64_t(double(budget) * double(back.size()) / double(total));
            const uint64_t budget_back = std::clamp<uint64_t>(share, back.size(), budget - front.size());
            const Aabb cell_back = child_cell(cell, c.plane, false), cell_front = child_cell(cell, c.plane, true);
            set = Set{};  // free the parent's fragments before descending
            stack.push_back({child + 1, std::move(front), cell_front, depth + 1, budget - budget_back});
            stack.push_back({child, std::move(back), cell_back, depth + 1, budget_back});
            return;
        }
        ++(over_budget ? out_.splinters.budget_capped : out_.splinters.unsplittable);
        make_leaf(node, set);
    }

    /// The child's cell box; when rounding leaves nothing of the parent's box on that side (a
    /// plane at the cell's face, with fragments lying in it), the parent's box stands in.
    static Aabb child_cell(const Aabb& cell, const BspPlane& plane, bool front) {
        const Aabb b = bsp_cut_box(cell, plane, front);
        return b.empty() ? cell : b;
    }

    void make_leaf(uint32_t node, const Set& set) {
        out_.nodes[node].index = uint32_t(out_.refs.size());
        out_.nodes[node].count = BspNode::kLeafBit | uint32_t(set.size());
        BspSplinters& s = out_.splinters;
        for (size_t i = 0; i < set.size(); ++i) {
            const uint32_t prim = frags_.prim(set, i);
            out_.refs.push_back(prim);
            ++pieces_[prim];
            if (frags_.is_piece(set, i)) {
                ++s.pieces;
                // Pieces of zero-area triangles have no size to speak of: left out of the figures.
                const double whole = frags_.prim_area(prim);
                if (whole > 0.0) {
                    const double area = frags_.area(set, i), ratio = area / whole;
                    if (s.measured_pieces == 0 || area < s.smallest_area) s.smallest_area = area;
                    if (s.measured_pieces == 0 || ratio < s.smallest_ratio) s.smallest_ratio = ratio;
                    s.slivers += ratio < kBspSliverRatio ? 1 : 0;
                    ++s.measured_pieces;
                }
            }
            if (keep_) {
                BspFragment f;
                f.leaf = node;
                f.prim = prim;
                f.box = frags_.bounds(set, i);
                frags_.polygon(set, i, f.polygon);
                keep_->push_back(std::move(f));
            }
        }
    }

    const Frags& frags_;
    const BspBuildOptions& options_;
    BspData& out_;
    std::vector<BspFragment>* keep_;
    std::vector<uint32_t> pieces_;  ///< fragments per primitive in leaves
    float scale_;                   ///< the scene's largest coordinate magnitude
    mutable Sample sample_;         ///< scratch of rank(), reused from node to node
    mutable std::vector<P3> points_;
};

template <class Frags>
BspData build_with(const Frags& frags, size_t prim_count, const Aabb& bounds, const BspBuildOptions& options,
                   std::vector<BspFragment>* keep) {
    check_options(options);
    if (prim_count >= (uint64_t(1) << 31)) throw Error("bsp: more than 2^31 primitives");
    BspData bsp;
    bsp.bounds = bounds;
    bsp.scale = scale_of(bounds);
    if (prim_count == 0) return bsp;
    Builder<Frags> builder(frags, options, prim_count, bsp, keep);
    builder.run(frags.initial(), uint64_t(options.fragment_budget) * prim_count);
    return bsp;
}

}  // namespace
}  // namespace bsp_build

BspData build_bsp_triangles(std::span<const std::array<Vec3, 3>> triangles, const BspBuildOptions& options,
                            std::vector<BspFragment>* fragments) {
    Aabb bounds;
    for (const auto& t : triangles)
        for (const Vec3& v : t) bounds.grow(v);
    const double tolerance = 0.5 * double(kBspPlaneBand) * double(bsp_build::scale_of(bounds));
    const bsp_build::PolygonFragments frags(triangles, tolerance);
    return bsp_build::build_with(frags, triangles.size(), bounds, options, fragments);
}

BspData build_bsp_boxes(std::span<const Aabb> bounds, const BspClip& clip, const BspBuildOptions& options,
                        std::vector<BspFragment>* fragments) {
    Aabb all;
    for (const Aabb& b : bounds) all.grow(b);
    const bsp_build::BoxFragments frags(bounds, clip);
    return bsp_build::build_with(frags, bounds.size(), all, options, fragments);
}

}  // namespace thicket
