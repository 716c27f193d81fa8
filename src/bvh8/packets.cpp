// The packet kernels' precondition, checked in baseline code before a group of rays is handed
// to them (Bvh8::intersect_chunk).
#include "thicket/bvh8/packets.h"

#include <cmath>

namespace thicket::bvh8 {

bool packet_eligible(const Ray* rays, uint32_t count) {
    auto octant = [](const Vec3& d, bool& finite) {
        const float inv[3] = {1.0f / d.x, 1.0f / d.y, 1.0f / d.z};
        int o = 0;
        for (int a = 0; a < 3; ++a) {
            finite = finite && std::isfinite(inv[a]);
            o |= int(std::signbit(inv[a])) << a;
        }
        return o;
    };
    bool finite = true;
    const int first = octant(rays[0].dir, finite);
    for (uint32_t k = 1; k < count && finite; ++k)
        if (octant(rays[k].dir, finite) != first) return false;
    return finite;
}

}  // namespace thicket::bvh8
