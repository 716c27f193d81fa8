// BIH payload: the root box, then the arrays as they are in memory (the BIH is relocatable),
// each preceded by its length. Reading checks the lengths against the scene before allocating,
// then the structure.
#include <istream>
#include <ostream>
#include <string>

#include "thicket/bih/build.h"
#include "thicket/core/error.h"

namespace thicket {

namespace {

template <class T>
void put(std::ostream& out, const T& v) {
    out.write(reinterpret_cast<const char*>(&v), sizeof(T));
}

template <class T>
void get(std::istream& in, T* data, size_t count, const char* what) {
    if (!in.read(reinterpret_cast<char*>(data), std::streamsize(count * sizeof(T))))
        throw Error(std::string("BIH payload truncated in ") + what);
}

}  // namespace

void write_bih(std::ostream& out, const BihData& bih) {
    put(out, bih.bounds);
    put(out, uint32_t(bih.nodes.size()));
    put(out, uint32_t(bih.prim_indices.size()));
    out.write(reinterpret_cast<const char*>(bih.nodes.data()), std::streamsize(bih.nodes.size() * sizeof(BihNode)));
    out.write(reinterpret_cast<const char*>(bih.prim_indices.data()),
              std::streamsize(bih.prim_indices.size() * sizeof(uint32_t)));
}

BihData read_bih(std::istream& in, size_t primitive_count) {
    BihData bih;
    uint32_t nodes = 0, prims = 0;
    get(in, &bih.bounds, 1, "bounds");
    get(in, &nodes, 1, "node count");
    get(in, &prims, 1, "primitive count");
    if (prims != primitive_count)
        throw Error("BIH payload holds " + std::to_string(prims) + " primitives, the scene " +
                    std::to_string(primitive_count));
    if (nodes > 4 * size_t(prims) + 1)
        throw Error("BIH payload claims " + std::to_string(nodes) + " nodes for " + std::to_string(prims) +
                    " primitives");
    bih.nodes.resize(nodes);
    bih.prim_indices.resize(prims);
    get(in, bih.nodes.data(), nodes, "nodes");
    get(in, bih.prim_indices.data(), prims, "primitive indices");
    if (in.peek() != std::char_traits<char>::eof()) throw Error("BIH payload has trailing bytes");
    validate_bih(bih, primitive_count);
    return bih;
}

}  // namespace thicket
