// Writing 8-wide nodes: from a binary BVH (collapse) or from a wide tree another builder made
// (write_wide_tree), with the tree's figures.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/bvh8/build.h"
#include "thicket/core/error.h"
#include "thicket/core/huge_pages.h"

namespace thicket::bvh8 {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Up to 8 lanes' source items, without a heap allocation per 8-wide node.
struct StaticKids {
    uint32_t items[kWidth];
    size_t n = 0;
    size_t size() const { return n; }
    void push_back(uint32_t v) { items[n++] = v; }
    uint32_t& operator[](size_t i) { return items[i]; }
};

/// The binary tree as the writer reads it: a node's lanes come from opening the interior child
/// of largest surface area until there are 8 or only leaves; a binary leaf, or a subtree of at
/// most merge_below primitives, is one leaf lane.
class BinarySource {
public:
    BinarySource(const BvhData& binary, uint32_t merge_below) : bin_(binary), merge_below_(merge_below) {
        reserve_huge(count_, bin_.nodes.size());
        reserve_huge(first_, bin_.nodes.size());
        count_.assign(bin_.nodes.size(), 0);
        first_.assign(bin_.nodes.size(), 0);
        count_subtrees();
    }
    bool empty() const { return bin_.nodes_used == 0; }
    /// At most one 8-wide node per binary interior node (about half the binary nodes).
    size_t node_bound() const { return bin_.nodes_used / 2 + 1; }
    Aabb bounds(uint32_t n) const { return bin_.nodes[n].bounds(); }
    bool is_leaf(uint32_t n) const { return bin_.nodes[n].is_leaf() || count_[n] <= merge_below_; }
    uint32_t first(uint32_t n) const { return first_[n]; }
    uint32_t count(uint32_t n) const { return count_[n]; }

    /// The lanes of the 8-wide node standing for binary node b (b itself if it is a leaf, which
    /// happens only at the root).
    void lanes(uint32_t b, StaticKids& kids) const {
        const BvhNode& bn = bin_.nodes[b];
        if (is_leaf(b)) {
            kids.push_back(b);
        } else {
            kids.push_back(bn.leftFirst);
            kids.push_back(bn.leftFirst + 1);
        }
        while (kids.size() < size_t(kWidth)) {
            int widest = -1;
            float widest_area = -1.0f;
            for (size_t i = 0; i < kids.size(); ++i) {
                const BvhNode& k = bin_.nodes[kids[i]];
                if (!is_leaf(kids[i]) && k.bounds().area() > widest_area) {
                    widest = int(i);
                    widest_area = k.bounds().area();
                }
            }
            if (widest < 0) break;
            const uint32_t open = kids[size_t(widest)];
            kids[size_t(widest)] = bin_.nodes[open].leftFirst;
            kids.push_back(bin_.nodes[open].leftFirst + 1);
        }
    }

private:
    /// Primitives under each binary node: a subtree's are contiguous in prim_indices (the
    /// builders partition in place), so they are one range. Children come after their parent in
    /// the pool, so one backward pass sees every child before its parent.
    void count_subtrees() {
        for (uint32_t n = bin_.nodes_used; n-- > 0;) {
            if (n == 1) continue;  // the unused slot
            const BvhNode& node = bin_.nodes[n];
            if (node.is_leaf()) {
                count_[n] = node.count;
                first_[n] = node.leftFirst;
                continue;
            }
            count_[n] = count_[node.leftFirst] + count_[node.leftFirst + 1];
            first_[n] = std::min(first_[node.leftFirst], first_[node.leftFirst + 1]);
        }
    }

    const BvhData& bin_;
    uint32_t merge_below_;
    std::vector<uint32_t> count_, first_;
};

/// A WideTree as the writer reads it: its nodes' children as they are.
class WideSource {
public:
    explicit WideSource(const WideTree& wide) : wide_(wide) {}
    bool empty() const { return wide_.items.empty(); }
    size_t node_bound() const { return wide_.items.size(); }
    Aabb bounds(uint32_t n) const { return wide_.items[n].box; }
    bool is_leaf(uint32_t n) const { return wide_.items[n].leaf; }
    uint32_t first(uint32_t n) const { return wide_.items[n].first; }
    uint32_t count(uint32_t n) const { return wide_.items[n].count; }
    void lanes(uint32_t n, StaticKids& kids) const {
        const WideTree::Item& item = wide_.items[n];
        if (item.leaf) {
            kids.push_back(n);
            return;
        }
        if (item.count > uint32_t(kWidth))
            throw Error("bvh8: a wide tree's node has " + std::to_string(item.count) + " children, more than 8");
        for (uint32_t i = 0; i < item.count; ++i) kids.push_back(wide_.children[item.first + i]);
    }

private:
    const WideTree& wide_;
};

/// Writes the 8-wide nodes of a Source (BinarySource, WideSource) depth first, lane 0's subtree
/// first, each leaf lane stored by `emit`, with the tree's figures.
template <class Source>
class Writer {
public:
    Writer(const Source& source, const LeafEmitter& emit, Tree& tree) : src_(source), emit_(emit), tree_(tree) {}

    /// A source item whose 8-wide node is still to be emitted, and the lane that will point to it.
    struct Pending {
        uint32_t item;
        size_t depth;
        uint32_t parent, lane;  ///< parent == kNoParent for the root
    };
    static constexpr uint32_t kNoParent = ~0u;

    /// Emits the 8-wide node standing for item b; returns its index. Its interior children are
    /// pushed on `stack` (first lane on top) to be emitted next, depth first.
    uint32_t emit_node(uint32_t b, size_t depth, std::vector<Pending>& stack) {
        tree_.max_depth = std::max(tree_.max_depth, depth);
        const uint32_t index = uint32_t(tree_.nodes.size());
        tree_.nodes.emplace_back();
        StaticKids kids;
        src_.lanes(b, kids);

        // Zeroed as a whole where it is stored: the 20 bytes of padding are saved with the node,
        // and a saved structure must be a function of the scene and the spec alone. (A node built
        // on the stack and assigned is not enough: a copy need not carry the padding.) Nothing
        // below grows tree_.nodes, so the reference holds.
        Node& node = tree_.nodes[index];
        std::memset(&node, 0, sizeof node);
        for (auto& axis : node.box) {
            std::fill(std::begin(axis[0]), std::end(axis[0]), kInf);
            std::fill(std::begin(axis[1]), std::end(axis[1]), -kInf);
        }
        const double root_area = root_area_;
        Aabb node_box;
        for (size_t lane = 0; lane < kids.size(); ++lane) {
            const Aabb k = src_.bounds(kids[lane]);
            node_box.grow(k);
            if (src_.is_leaf(kids[lane])) {
                const uint32_t count = src_.count(kids[lane]);
                const LeafPlacement p = emit_(src_.first(kids[lane]), count);
                if (p.size == 0) continue;
                if (p.size > 255)
                    throw Error("bvh8: a leaf of " + std::to_string(count) + " primitives needs " +
                                std::to_string(p.size) + " slots, more than the 255 a lane can hold");
                node.child[lane] = p.first;
                node.leaf_size[lane] = uint8_t(p.size);
                ++tree_.leaves;
                tree_.max_depth = std::max(tree_.max_depth, depth + 1);
                const double area_ratio = root_area > 0 ? double(k.area()) / root_area : 0.0;
                tree_.sah_cost += kSahIntersectionCost * area_ratio * count;
                tree_.embree_sah_cost += area_ratio * double((count + 3) / 4);
            }
            for (int a = 0; a < 3; ++a) {
                node.box[a][0][lane] = k.min[a];
                node.box[a][1][lane] = k.max[a];
            }
            node.valid |= 1u << lane;
        }
        const double area_ratio = root_area > 0 ? double(node_box.area()) / root_area : 0.0;
        tree_.sah_cost += kSahTraversalCost * area_ratio;
        tree_.embree_sah_cost += area_ratio;
        // Children after the parent, depth first: the last lane pushed first, so lane 0 is next.
        for (size_t lane = kids.size(); lane-- > 0;)
            if ((node.valid >> lane & 1) && !src_.is_leaf(kids[lane]))
                stack.push_back({kids[lane], depth + 1, index, uint32_t(lane)});
        return index;
    }

    void run() {
        if (src_.empty()) return;
        reserve_huge(tree_.nodes, src_.node_bound());
        tree_.bounds = src_.bounds(0);
        root_area_ = tree_.bounds.area();
        std::vector<Pending> stack{{0, 1, kNoParent, 0}};
        while (!stack.empty()) {
            const Pending p = stack.back();
            stack.pop_back();
            const uint32_t index = emit_node(p.item, p.depth, stack);
            if (p.parent != kNoParent) tree_.nodes[p.parent].child[p.lane] = index;
        }
    }

private:
    const Source& src_;
    const LeafEmitter& emit_;
    Tree& tree_;
    double root_area_ = 0.0;
};

}  // namespace

size_t block_count(const BvhData& binary, uint32_t merge_below) {
    if (binary.nodes_used == 0) return 0;
    // Children come after their parent: one backward pass sees both before the parent. A lane's
    // leaf is the first node from the top that is a binary leaf or holds at most merge_below
    // (Collapser::is_leaf), so a node's figure is its own blocks if it is one, else its children's.
    std::vector<uint32_t> count(binary.nodes_used, 0);
    std::vector<size_t> blocks(binary.nodes_used, 0);
    for (uint32_t n = binary.nodes_used; n-- > 0;) {
        if (n == 1) continue;  // the unused slot
        const BvhNode& node = binary.nodes[n];
        const uint32_t l = node.leftFirst;
        count[n] = node.is_leaf() ? node.count : count[l] + count[l + 1];
        blocks[n] = node.is_leaf() || count[n] <= merge_below ? (size_t(count[n]) + 3) / 4 : blocks[l] + blocks[l + 1];
    }
    return blocks[0];
}

Tree collapse(const BvhData& binary, const LeafEmitter& emit, uint32_t merge_below) {
    Tree tree;
    const BinarySource source(binary, merge_below);
    Writer<BinarySource>(source, emit, tree).run();
    return tree;
}

Tree write_wide_tree(const WideTree& wide, const LeafEmitter& emit) {
    Tree tree;
    const WideSource source(wide);
    Writer<WideSource>(source, emit, tree).run();
    return tree;
}

size_t block_count(const WideTree& wide) {
    size_t blocks = 0;
    for (const WideTree::Item& item : wide.items)
        if (item.leaf) blocks += (size_t(item.count) + 3) / 4;
    return blocks;
}

void validate_tree(const Tree& tree, size_t leaf_slots) {
    for (size_t n = 0; n < tree.nodes.size(); ++n) {
        const Node& node = tree.nodes[n];
        for (int lane = 0; lane < kWidth; ++lane) {
            const std::string where = "bvh8: node " + std::to_string(n) + " lane " + std::to_string(lane);
            if (!(node.valid >> lane & 1)) {
                for (int a = 0; a < 3; ++a)
                    if (!(node.box[a][0][lane] > node.box[a][1][lane])) throw Error(where + ": empty lane not inverted");
                continue;
            }
            if (node.leaf_size[lane] == 0) {
                if (node.child[lane] <= n || node.child[lane] >= tree.nodes.size())
                    throw Error(where + ": child node " + std::to_string(node.child[lane]) + " out of order or range");
            } else if (size_t(node.child[lane]) + node.leaf_size[lane] > leaf_slots) {
                throw Error(where + ": leaf beyond the " + std::to_string(leaf_slots) + " slots stored");
            }
        }
    }
}

}  // namespace thicket::bvh8
