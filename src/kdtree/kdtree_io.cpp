// kD-tree payload: counts, the root voxel, then the arrays as they are in memory (the tree is
// relocatable). Reading checks the counts against the bytes present before allocating, then the
// structure.
#include <istream>
#include <ostream>

#include "thicket/core/error.h"
#include "thicket/util/binary_io.h"
#include "thicket/kdtree/build.h"

namespace thicket {

void write_kdtree(std::ostream& out, const KdTreeData& tree) {
    write_value(out, tree.primitives);
    write_value(out, uint32_t(tree.nodes.size()));
    write_value(out, uint32_t(tree.prim_indices.size()));
    write_value(out, tree.bounds);
    write_array(out, tree.nodes.data(), tree.nodes.size());
    write_array(out, tree.prim_indices.data(), tree.prim_indices.size());
}

KdTreeData read_kdtree(std::istream& in, size_t primitive_count) {
    PayloadReader reader(in, "kD-tree");
    KdTreeData tree;
    uint32_t nodes = 0, refs = 0;
    reader.value(tree.primitives, "primitive count");
    reader.value(nodes, "node count");
    reader.value(refs, "reference count");
    reader.value(tree.bounds, "root voxel");
    if (tree.primitives != primitive_count)
        throw Error("kD-tree payload holds " + std::to_string(tree.primitives) + " primitives, the scene " +
                    std::to_string(primitive_count));
    // The payload must hold exactly the arrays it announces: checked before allocating them.
    const auto here = in.tellg();
    in.seekg(0, std::ios::end);
    const auto end = in.tellg();
    in.seekg(here);
    const uint64_t want = uint64_t(nodes) * sizeof(KdNode) + uint64_t(refs) * sizeof(uint32_t);
    if (here < 0 || end < here || uint64_t(end - here) != want)
        throw Error("kD-tree payload size does not match its " + std::to_string(nodes) + " nodes and " +
                    std::to_string(refs) + " references");
    tree.nodes.resize(nodes);
    tree.prim_indices.resize(refs);
    reader.array(tree.nodes.data(), nodes, "nodes");
    reader.array(tree.prim_indices.data(), refs, "primitive references");
    validate_kdtree(tree, primitive_count);
    return tree;
}

}  // namespace thicket
