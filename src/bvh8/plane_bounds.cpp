// The plane bounds of a tree (TraceContext::plane_lo/hi), computed in baseline code once per
// build or load.
#include "thicket/bvh8/node.h"

namespace thicket::bvh8 {

void set_plane_bounds(TraceContext& ctx, const Node* nodes, size_t count) {
    float lo[3] = {__builtin_inff(), __builtin_inff(), __builtin_inff()};
    float hi[3] = {-__builtin_inff(), -__builtin_inff(), -__builtin_inff()};
    for (size_t k = 0; k < count; ++k)
        for (int lane = 0; lane < kWidth; ++lane) {
            if (!((nodes[k].valid >> lane) & 1u)) continue;
            for (int a = 0; a < 3; ++a)
                for (int side = 0; side < 2; ++side) {
                    const float x = nodes[k].box[a][side][lane];
                    if (x < lo[a]) lo[a] = x;  // a NaN plane is skipped: it never narrows a slab
                    if (x > hi[a]) hi[a] = x;
                }
        }
    for (int a = 0; a < 3; ++a) ctx.plane_lo[a] = lo[a], ctx.plane_hi[a] = hi[a];
}

}  // namespace thicket::bvh8
