// Reinsertion optimizer (Bittner, Hapala & Havran 2013): a built tree's worst-placed nodes (the
// largest boxes) are taken out one at a time and put back where the surface area of all interior
// nodes grows least, found by branch and bound from the root. Leaves are never changed, so the
// SAH cost moves only with the interior areas, and a move is made only when it lowers them. The
// tree is then laid out again in the lecture's form (sibling pairs, contiguous subtrees).
#include <algorithm>
#include <numeric>
#include <queue>
#include <vector>

#include "splitter.h"
#include "thicket/bvh/reinsertion.h"

namespace thicket {

namespace {

constexpr uint32_t kNone = ~0u;

/// The tree as linked nodes (indices of the built pool), which a move can rewire cheaply.
struct Linked {
    std::vector<uint32_t> left, right, parent;
    std::vector<Aabb> box;
    uint32_t root = 0;

    bool leaf(uint32_t n) const { return left[n] == kNone; }
};

Linked link(const BvhData& bvh) {
    const size_t n = bvh.nodes_used;
    Linked t{std::vector<uint32_t>(n, kNone), std::vector<uint32_t>(n, kNone), std::vector<uint32_t>(n, kNone),
             std::vector<Aabb>(n), 0};
    for (uint32_t i = 0; i < n; ++i) {
        if (i == 1) continue;
        const BvhNode& node = bvh.nodes[i];
        t.box[i] = node.bounds();
        if (node.is_leaf()) continue;
        t.left[i] = node.leftFirst;
        t.right[i] = node.leftFirst + 1;
        t.parent[node.leftFirst] = t.parent[node.leftFirst + 1] = i;
    }
    return t;
}

/// Boxes from `from` up to the root become their children's union again.
void refit(Linked& t, uint32_t from) {
    for (uint32_t n = from; n != kNone; n = t.parent[n]) {
        Aabb b = t.box[t.left[n]];
        b.grow(t.box[t.right[n]]);
        t.box[n] = b;
    }
}

/// Replaces child `old_child` of `parent` by `new_child`.
void replace_child(Linked& t, uint32_t parent, uint32_t old_child, uint32_t new_child) {
    (t.left[parent] == old_child ? t.left[parent] : t.right[parent]) = new_child;
    t.parent[new_child] = parent;
}

/// The node whose sibling `n` should become for the least growth of interior area (branch and
/// bound over induced cost), and that growth.
std::pair<uint32_t, float> best_position(const Linked& t, const Aabb& box) {
    struct Item {
        float induced;
        uint32_t node;
        bool operator<(const Item& o) const { return induced > o.induced || (induced == o.induced && node > o.node); }
    };
    std::priority_queue<Item> queue;
    queue.push({0.0f, t.root});
    uint32_t best = t.root;
    float best_cost = kInfinity;
    const float own = box.half_area();
    while (!queue.empty()) {
        const Item it = queue.top();
        queue.pop();
        if (it.induced + own >= best_cost) break;  // nothing left can beat the best
        Aabb merged = t.box[it.node];
        merged.grow(box);
        const float direct = merged.half_area();
        if (it.induced + direct < best_cost) {
            best_cost = it.induced + direct;
            best = it.node;
        }
        if (!t.leaf(it.node)) {
            const float induced = it.induced + direct - t.box[it.node].half_area();
            if (induced + own < best_cost) {
                queue.push({induced, t.left[it.node]});
                queue.push({induced, t.right[it.node]});
            }
        }
    }
    return {best, best_cost};
}

/// Tries to move node n (not the root nor a child of it); returns whether it moved.
bool reinsert(Linked& t, uint32_t n) {
    const uint32_t p = t.parent[n];
    const uint32_t g = t.parent[p];
    const uint32_t s = t.left[p] == n ? t.right[p] : t.left[p];
    // Take n and its parent out: the sibling takes the parent's place.
    float removed = t.box[p].half_area();
    replace_child(t, g, p, s);
    for (uint32_t a = g; a != kNone; a = t.parent[a]) {
        const float before = t.box[a].half_area();
        Aabb b = t.box[t.left[a]];
        b.grow(t.box[t.right[a]]);
        t.box[a] = b;
        removed += before - b.half_area();
    }
    const auto [x, added] = best_position(t, t.box[n]);
    // The old place is a candidate too (x == s costs exactly `removed`): move only on a clear gain.
    const uint32_t target = added < removed * (1.0f - 1e-6f) ? x : s;
    const uint32_t xp = t.parent[target];
    if (xp == kNone) {
        t.root = p;
        t.parent[p] = kNone;
    } else {
        replace_child(t, xp, target, p);
    }
    t.left[p] = target;
    t.right[p] = n;
    t.parent[target] = t.parent[n] = p;
    refit(t, p);
    return target != s;
}

/// Sum of interior half areas: what reinsertion lowers (leaves never change).
double interior_area(const Linked& t) {
    double sum = 0;
    std::vector<uint32_t> stack{t.root};
    while (!stack.empty()) {
        const uint32_t n = stack.back();
        stack.pop_back();
        if (t.leaf(n)) continue;
        sum += t.box[n].half_area();
        stack.push_back(t.left[n]);
        stack.push_back(t.right[n]);
    }
    return sum;
}

size_t depth_of(const Linked& t) {
    size_t deepest = 0;
    std::vector<std::pair<uint32_t, size_t>> stack{{t.root, 0}};
    while (!stack.empty()) {
        const auto [n, d] = stack.back();
        stack.pop_back();
        deepest = std::max(deepest, d);
        if (t.leaf(n)) continue;
        stack.push_back({t.left[n], d + 1});
        stack.push_back({t.right[n], d + 1});
    }
    return deepest;
}

/// Writes the linked tree back in the lecture's layout: depth-first pairs, each subtree's
/// primitives contiguous, the left child of each pair on the lower side of its split axis.
void relayout(const Linked& t, BvhData& bvh) {
    BvhData out;
    out.nodes.resize(bvh.nodes.size());
    out.child_order.assign(bvh.child_order.size(), 0);
    out.prim_indices.reserve(bvh.prim_indices.size());
    out.nodes_used = 2;
    struct Item {
        uint32_t from, to;
    };
    std::vector<Item> stack{{t.root, 0}};
    while (!stack.empty()) {
        const auto [from, to] = stack.back();
        stack.pop_back();
        BvhNode& node = out.nodes[to];
        node.aabbMin = t.box[from].min;
        node.aabbMax = t.box[from].max;
        if (t.leaf(from)) {
            const BvhNode& old = bvh.nodes[from];
            node.leftFirst = uint32_t(out.prim_indices.size());
            node.count = old.count;
            out.prim_indices.insert(out.prim_indices.end(), bvh.prim_indices.begin() + old.leftFirst,
                                    bvh.prim_indices.begin() + old.leftFirst + old.count);
            continue;
        }
        uint32_t a = t.left[from], b = t.right[from];
        const Vec3 ca = t.box[a].center(), cb = t.box[b].center();
        const int axis = max_axis(abs(cb - ca));
        if (ca[axis] > cb[axis]) std::swap(a, b);
        const uint32_t pair = out.nodes_used;
        out.nodes_used += 2;
        node.leftFirst = pair;
        node.count = 0;
        out.child_order[to] = ChildOrder::pack(axis, axis, false);
        stack.push_back({b, pair + 1});
        stack.push_back({a, pair});
    }
    bvh = std::move(out);
}

}  // namespace

ReinsertionFigures optimize_reinsertion(BvhData& bvh, int passes) {
    ReinsertionFigures f;
    if (bvh.nodes_used < 8) return f;  // nothing below the root's grandchildren to move
    Linked t = link(bvh);
    f.area_before = f.area_after = interior_area(t);
    for (int pass = 0; pass < passes; ++pass) {
        // Candidates: every node below the root's children, largest box first (Bittner et al.
        // rank by area too); ties by index so the order is fixed.
        std::vector<uint32_t> nodes;
        for (uint32_t i = 0; i < t.box.size(); ++i)
            if (i != 1 && i != t.root && t.parent[i] != kNone && t.parent[t.parent[i]] != kNone) nodes.push_back(i);
        const size_t take = std::max<size_t>(1, nodes.size() / 20);
        std::partial_sort(nodes.begin(), nodes.begin() + ptrdiff_t(take), nodes.end(), [&](uint32_t a, uint32_t b) {
            const float aa = t.box[a].half_area(), ab = t.box[b].half_area();
            return aa > ab || (aa == ab && a < b);
        });
        const Linked before = t;
        size_t moved = 0;
        for (size_t k = 0; k < take; ++k) {
            const uint32_t n = nodes[k];
            if (t.parent[n] == kNone || t.parent[t.parent[n]] == kNone) continue;  // moved next to the root
            moved += reinsert(t, n) ? 1 : 0;
        }
        const double area = interior_area(t);
        // Rounding in the refits could in principle add area, and moves can deepen the tree:
        // a pass that does either is undone, so the result never costs more nor breaks the bound.
        if (!(area < f.area_after) || depth_of(t) > kMaxSahDepth) {
            t = before;
            break;
        }
        f.area_after = area;
        f.moves += moved;
        ++f.passes;
        if (moved == 0) break;
    }
    if (f.passes > 0) relayout(t, bvh);
    return f;
}

}  // namespace thicket
