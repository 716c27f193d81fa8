// BVH payload: the arrays as they are in memory (the BVH is relocatable), each preceded by its
// length. Reading checks every length against the scene before allocating, then the structure.
#include <istream>
#include <ostream>

#include "thicket/bvh/build.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

template <class T>
void put(std::ostream& out, const T& v) {
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
void get(std::istream& in, T& v, const char* what) {
    if (!in.read(reinterpret_cast<char*>(&v), sizeof(T))) throw Error(std::string("BVH payload truncated in ") + what);
}

template <class T>
void get_array(std::istream& in, T* data, size_t count, const char* what) {
    if (!in.read(reinterpret_cast<char*>(data), std::streamsize(count * sizeof(T))))
        throw Error(std::string("BVH payload truncated in ") + what);
}

}  // namespace

void write_bvh(std::ostream& out, const BvhData& bvh) {
    put(out, uint32_t(bvh.nodes_used));
    put(out, uint32_t(bvh.prim_indices.size()));
    out.write(reinterpret_cast<const char*>(bvh.nodes.data()), std::streamsize(bvh.nodes_used * sizeof(BvhNode)));
    out.write(reinterpret_cast<const char*>(bvh.child_order.data()), std::streamsize(bvh.nodes_used));
    out.write(reinterpret_cast<const char*>(bvh.prim_indices.data()),
              std::streamsize(bvh.prim_indices.size() * sizeof(uint32_t)));
}

BvhData read_bvh(std::istream& in, size_t primitive_count) {
    uint32_t nodes_used = 0, prims = 0;
    get(in, nodes_used, "node count");
    get(in, prims, "primitive count");
    if (prims != primitive_count)
        throw Error("BVH payload holds " + std::to_string(prims) + " primitives, the scene " +
                    std::to_string(primitive_count));
    if (nodes_used > 2 * size_t(prims))
        throw Error("BVH payload claims " + std::to_string(nodes_used) + " nodes for " + std::to_string(prims) +
                    " primitives");
    BvhData bvh;
    bvh.nodes_used = nodes_used;
    bvh.nodes.resize(nodes_used);
    bvh.child_order.resize(nodes_used);
    bvh.prim_indices.resize(prims);
    get_array(in, bvh.nodes.data(), nodes_used, "nodes");
    get_array(in, bvh.child_order.data(), nodes_used, "child order");
    get_array(in, bvh.prim_indices.data(), prims, "primitive indices");
    if (in.peek() != std::char_traits<char>::eof()) throw Error("BVH payload has trailing bytes");
    validate_bvh(bvh, primitive_count);
    return bvh;
}

}  // namespace thicket
