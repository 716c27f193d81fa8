// Octree payload: the root cell, then the nodes and the leaves' primitive ids as they are in
// memory (the tree is relocatable), each preceded by its length. Reading checks the lengths
// against the bounds and the bytes left before allocating (PayloadReader), then the structure;
// the proof over the primitives is validate_octree_coverage's.
#include <istream>
#include <ostream>
#include <string>
#include <vector>

#include "thicket/core/error.h"
#include "thicket/octree/build.h"
#include "thicket/util/binary_io.h"

namespace thicket {

void write_octree(std::ostream& out, const OctreeData& tree) {
    write_value(out, tree.root);
    write_counted_array<uint64_t>(out, tree.nodes);
    write_counted_array<uint64_t>(out, tree.refs);
}

OctreeData read_octree(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "octree");
    OctreeData tree;
    reader.value(tree.root, "root cell");
    reader.counted_array<uint64_t>(tree.nodes, kOctreeMaxNodes, "nodes");
    reader.counted_array<uint64_t>(tree.refs, octree_reference_budget(primitive_count), "references");
    reader.end();
    validate_octree(tree, primitive_count);
    return tree;
}

void validate_octree(const OctreeData& tree, size_t primitive_count) {
    if (tree.nodes.empty()) {
        if (!tree.refs.empty()) throw Error("invalid octree: references but no nodes");
        return;
    }
    if (tree.nodes.size() > kOctreeMaxNodes || tree.refs.size() >= OctreeNode::kInner)
        throw Error("invalid octree: too many nodes or references");
    for (const uint32_t r : tree.refs)
        if (r >= primitive_count)
            throw Error("invalid octree: reference to primitive " + std::to_string(r) + " of " +
                        std::to_string(primitive_count));
    // Level by level from the root: children after their parent, each node reached once.
    std::vector<uint8_t> reached(tree.nodes.size(), 0);
    std::vector<uint32_t> level{0}, next;
    reached[0] = 1;
    size_t count = 1;
    for (uint32_t depth = 0; !level.empty(); ++depth) {
        next.clear();
        for (const uint32_t n : level) {
            const OctreeNode& node = tree.nodes[n];
            if (node.is_leaf()) {
                if (uint64_t(node.index) + node.count > tree.refs.size())
                    throw Error("invalid octree: leaf " + std::to_string(n) + " references out of range");
                continue;
            }
            if (depth == kOctreeMaxDepth) throw Error("invalid octree: deeper than " + std::to_string(kOctreeMaxDepth));
            if (node.index <= n || uint64_t(node.index) + 8 > tree.nodes.size())
                throw Error("invalid octree: node " + std::to_string(n) + " has children out of range");
            for (uint32_t c = node.index; c < node.index + 8; ++c) {
                if (reached[c]) throw Error("invalid octree: node " + std::to_string(c) + " has two parents");
                reached[c] = 1;
                next.push_back(c);
            }
            count += 8;
        }
        level.swap(next);
    }
    if (count != tree.nodes.size())
        throw Error("invalid octree: " + std::to_string(tree.nodes.size() - count) + " nodes are unreachable");
}

}  // namespace thicket
