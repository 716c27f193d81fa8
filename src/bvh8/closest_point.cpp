// bvh8's closest-point query: the leaf test over 4-triangle blocks, called back by the per-ISA
// traversal. Compiled for the baseline, like the rest of the structure: it uses the shared inline
// point-triangle test, which must never be compiled into a kernel file (docs/bvh8.md).
#include "thicket/bvh8/closest_point.h"

#include <algorithm>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace thicket::bvh8 {

namespace {

/// Box distances are computed apart from the leaf test's exact ones, each with its own rounding:
/// the bound is widened (1.5e-5 relative, far above either's error and far below what would open
/// more boxes), so that a box holding a triangle exactly as close as the best (a shared vertex or
/// edge, which the lower id wins) is never pruned by rounding.
constexpr float kBoundSlack = 1.0f + 1.0f / 65536.0f;

/// The squared bound that prunes boxes once the best point is `distance` away (+inf: none yet).
float bound_of(float distance) { return distance * distance * kBoundSlack; }
/// Mask of the block's lanes whose triangle's box lies within bound2 (squared) of p: each axis's
/// max(max(lo - p, p - hi), 0), squared and summed. Four lanes at once with SSE2, the x86-64
/// baseline (this lane prefilter is most of a leaf's cost); the same operations lane by lane
/// elsewhere. Unused lanes (all-zero vertices) may pass: the caller skips their ids.
uint32_t lanes_within(const Tri4& b, const Vec3& p, float bound2) {
#if defined(__SSE2__)
    const __m128 zero = _mm_setzero_ps();
    __m128 sum = zero;
    for (int a = 0; a < 3; ++a) {
        const __m128 v0 = _mm_load_ps(b.v[0][a]), v1 = _mm_load_ps(b.v[1][a]), v2 = _mm_load_ps(b.v[2][a]);
        const __m128 lo = _mm_min_ps(v0, _mm_min_ps(v1, v2)), hi = _mm_max_ps(v0, _mm_max_ps(v1, v2));
        const __m128 pa = _mm_set1_ps(p[a]);
        const __m128 d = _mm_max_ps(_mm_max_ps(_mm_sub_ps(lo, pa), _mm_sub_ps(pa, hi)), zero);
        sum = _mm_add_ps(sum, _mm_mul_ps(d, d));
    }
    return uint32_t(_mm_movemask_ps(_mm_cmple_ps(sum, _mm_set1_ps(bound2))));
#else
    uint32_t mask = 0;
    for (int lane = 0; lane < 4; ++lane) {
        float sum = 0.0f;
        for (int a = 0; a < 3; ++a) {
            const float v0 = b.v[0][a][lane], v1 = b.v[1][a][lane], v2 = b.v[2][a][lane];
            const float lo = std::min(v0, std::min(v1, v2)), hi = std::max(v0, std::max(v1, v2));
            const float d = std::max(std::max(lo - p[a], p[a] - hi), 0.0f);
            sum += d * d;
        }
        if (sum <= bound2) mask |= 1u << lane;
    }
    return mask;
#endif
}

/// A query in flight: the point, the blocks of the tree being searched, the best point so far.
struct PointQuery {
    Vec3 p;
    const Tri4* blocks;
    NearestPoint best;
};

/// PointLeafFn over the blocks [first, first + size): each used lane whose triangle's box lies
/// within the bound gets the exact test (most lanes of an opened leaf are farther than the best
/// point, and the exact test costs several box tests).
float closest_in_blocks(void* query, uint32_t first, uint32_t size) {
    PointQuery& q = *static_cast<PointQuery*>(query);
    for (uint32_t k = first; k < first + size; ++k) {
        const Tri4& b = q.blocks[k];
        uint32_t lanes = lanes_within(b, q.p, bound_of(q.best.distance));
        while (lanes) {
            const int lane = __builtin_ctz(lanes);
            lanes &= lanes - 1;
            const uint32_t id = b.id[lane];
            if (id == kNoPrim) continue;  // unused lane: all-zero vertices, no triangle
            const Vec3 v0{b.v[0][0][lane], b.v[0][1][lane], b.v[0][2][lane]};
            const Vec3 v1{b.v[1][0][lane], b.v[1][1][lane], b.v[1][2][lane]};
            const Vec3 v2{b.v[2][0][lane], b.v[2][1][lane], b.v[2][2][lane]};
            // Triangles::closest_point's expression, operation for operation.
            const TrianglePoint t = closest_point_on_triangle(q.p, v0, v1, v2);
            const float d = point_distance(q.p, t.point);
            if (d < q.best.distance || (d == q.best.distance && id < q.best.prim)) q.best = {t.point, d, t.u, t.v, id};
        }
    }
    return bound_of(q.best.distance);
}

}  // namespace

NearestPoint closest_point(const KernelTable& kernels, const TraceContext* tree, const Vec3& p) {
    // The kernel sees the best only through the bound the leaf test returns.
    PointQuery q{p, nullptr, NearestPoint{}};
    if (!tree) return q.best;
    const float point[3] = {p.x, p.y, p.z};
    q.blocks = tree->blocks;
    kernels.closest_point(*tree, point, bound_of(q.best.distance), &closest_in_blocks, &q);
    return q.best;
}

}  // namespace thicket::bvh8
