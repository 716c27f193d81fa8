// kD-tree payload: counts, the root voxel, then the arrays as they are in memory (the tree is
// relocatable). Reading checks the counts against the bytes left before allocating
// (PayloadReader), then the structure.
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
    // Node indices are 30-bit fields; references are bounded by the bytes left only (perfect
    // splits may list a primitive in many leaves).
    reader.array(tree.nodes, nodes, uint64_t(kKdMaxField) + 1, "nodes");
    reader.array(tree.prim_indices, refs, PayloadReader::kAnyCount, "primitive references");
    reader.end();
    validate_kdtree(tree, primitive_count);
    return tree;
}

}  // namespace thicket
