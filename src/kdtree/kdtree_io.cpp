// kD-tree payload: counts, the root voxel, then the arrays as they are in memory (the tree is
// relocatable). Reading checks the counts against the bytes present before allocating, then the
// structure.
#include <istream>
#include <ostream>

#include "thicket/core/error.h"
#include "thicket/kdtree/build.h"

namespace thicket {

namespace {

template <class T>
void put(std::ostream& out, const T& v) {
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
void get(std::istream& in, T* data, size_t count, const char* what) {
    if (!in.read(reinterpret_cast<char*>(data), std::streamsize(count * sizeof(T))))
        throw Error(std::string("kD-tree payload truncated in ") + what);
}

}  // namespace

void write_kdtree(std::ostream& out, const KdTreeData& tree) {
    put(out, tree.primitives);
    put(out, uint32_t(tree.nodes.size()));
    put(out, uint32_t(tree.prim_indices.size()));
    put(out, tree.bounds);
    out.write(reinterpret_cast<const char*>(tree.nodes.data()), std::streamsize(tree.nodes.size() * sizeof(KdNode)));
    out.write(reinterpret_cast<const char*>(tree.prim_indices.data()),
              std::streamsize(tree.prim_indices.size() * sizeof(uint32_t)));
}

KdTreeData read_kdtree(std::istream& in, size_t primitive_count) {
    KdTreeData tree;
    uint32_t nodes = 0, refs = 0;
    get(in, &tree.primitives, 1, "primitive count");
    get(in, &nodes, 1, "node count");
    get(in, &refs, 1, "reference count");
    get(in, &tree.bounds, 1, "root voxel");
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
    get(in, tree.nodes.data(), nodes, "nodes");
    get(in, tree.prim_indices.data(), refs, "primitive references");
    validate_kdtree(tree, primitive_count);
    return tree;
}

}  // namespace thicket
