// Packing triangles into 4-lane blocks, and what the blocks hold.
#include "thicket/bvh8/blocks.h"

#include <algorithm>

#include "thicket/core/ray.h"
#include "thicket/prims/triangles.h"

namespace thicket::bvh8 {

template <class Tris>
LeafPlacement pack_blocks(Blocks& blocks, const Tris& tris, const uint32_t* prims, uint32_t count,
                          BlockPacking& packing) {
    LeafPlacement p{uint32_t(blocks.size()), 0};
    uint32_t lane = 4;
    for (uint32_t k = 0; k < count; ++k) {
        if (packing.may_repeat && std::find(prims, prims + k, prims[k]) != prims + k) continue;
        const auto v = tris.triangle(prims[k]);
        if (lane == 4) {
            blocks.emplace_back();
            Tri4& b = blocks.back();
            for (auto& vertex : b.v)
                for (auto& axis : vertex)
                    for (float& x : axis) x = 0.0f;
            for (uint32_t& id : b.id) id = kNoPrim;
            lane = 0;
            ++p.size;
        }
        Tri4& b = blocks.back();
        for (int vertex = 0; vertex < 3; ++vertex)
            for (int a = 0; a < 3; ++a) b.v[vertex][a][lane] = v[size_t(vertex)][a];
        b.id[lane] = prims[k];
        ++lane;
        ++packing.lanes;
    }
    return p;
}

size_t degenerate_lanes(const Blocks& blocks) {
    size_t count = 0;
    for (const Tri4& b : blocks)
        for (int lane = 0; lane < 4; ++lane) {
            if (b.id[lane] == kNoPrim) continue;
            Triangles<>::Tri tri;
            Vec3* corners[3] = {&tri.v0, &tri.v1, &tri.v2};
            for (int vertex = 0; vertex < 3; ++vertex)
                *corners[vertex] = Vec3(b.v[vertex][0][lane], b.v[vertex][1][lane], b.v[vertex][2][lane]);
            count += Triangles<>::degenerate(tri) ? 1 : 0;
        }
    return count;
}

template LeafPlacement pack_blocks(Blocks&, const Triangles<TriangleTest::Moller>&, const uint32_t*, uint32_t,
                                   BlockPacking&);
template LeafPlacement pack_blocks(Blocks&, const Triangles<TriangleTest::Watertight>&, const uint32_t*, uint32_t,
                                   BlockPacking&);

}  // namespace thicket::bvh8
