#pragma once
/// Reordered batches (issue 43): an incoherent batch traced in the order its rays were given
/// sends each ray to a different part of the tree from the one before, so most nodes and leaves
/// it visits miss the nearer caches. Sorted in blocks by direction octant and by the Morton code
/// of the origin, neighbouring rays start in the same region and walk the same nodes. That pays
/// only where a ray costs far more than its share of the sort, the gather and the scatter back:
/// expensive rays (the interior scenes' diffuse and random sets) trace up to 1.1-1.2x faster,
/// cheap ones (rays that leave an exterior scene at once) lose up to 2x. So each block's first two
/// chunks are traced as given, the second timed (the first may meet a cold structure), and the
/// rest of the block is sorted only when that chunk took at least kReorderFromNs a ray
/// (BENCHMARKS.md, "Reordered batches"). The answers are the same either way: each ray is traced
/// alone, only the order in which they are traced changes. Off by default (BatchOptions::reorder):
/// rays that start on a surface in image order (a renderer's diffuse bounces) were already local,
/// and the octant-first order lost 0.83-0.89x on the dragon's.
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "thicket/accel/accel.h"
#include "thicket/core/vec3.h"

namespace thicket {

/// Batches of fewer rays are traced as given: a sort pays for itself only over enough rays.
inline constexpr size_t kReorderMin = 4096;
/// The largest block sorted at once: 2 MiB of rays, which the caches hold while they are traced.
inline constexpr size_t kReorderBlock = 65536;
// kReorderFromNs, the cost a ray from which a block is sorted by default, is in accel.h beside
// BatchOptions::reorder_from_ns.

/// The cost a ray from which a batch traced with `options` is sorted: infinity when it is not
/// reordered at all (BatchOptions::reorder false, or a coherent batch, whose order is the point).
inline double reorder_from(const BatchOptions& options) {
    return options.reorder && !options.coherent ? options.reorder_from_ns : INFINITY;
}

/// The block size for a reordered batch of `count` rays on `workers` threads: kReorderBlock, or
/// less so that every worker gets at least two blocks; a multiple of 256 (a packet and chunk size).
size_t reorder_block(size_t count, unsigned workers);

/// Times f() over `rays` rays and says whether they cost at least `from_ns` a ray.
template <class F>
bool costly_rays(size_t rays, double from_ns, F&& f) {
    const auto start = std::chrono::steady_clock::now();
    f();
    const std::chrono::duration<double, std::nano> took = std::chrono::steady_clock::now() - start;
    return took.count() >= from_ns * double(rays);
}

/// Sort keys and the scratch of one block, kept by the thread that orders it.
struct RayOrder {
    std::vector<uint32_t> keys;
    std::vector<uint64_t> pairs, scratch;
    std::vector<uint32_t> order;  ///< order[k]: the block-relative index of the k-th ray to trace

    /// Fills `order` with the permutation of [0, n) that lists ray i (origin and direction
    /// `ray(i, org, dir)`) by direction octant, then by the Morton code of its origin quantised to
    /// kOriginBits per axis over the finite origins' bounds; equal keys keep their input order. A
    /// non-finite or NaN component gets some key, never undefined behaviour: such rays are
    /// answered as misses wherever they land.
    template <class RayAt>
    void sort(size_t n, RayAt&& ray);

    /// Bits of each origin coordinate in the key: 64 cells a side hold a 65536-ray block's
    /// origins at about one ray a cell for the random set; finer cells traced no faster (A/B,
    /// BENCHMARKS.md) and needed a third pass of the sort.
    static constexpr int kOriginBits = 6;
    static constexpr int kKeyBits = 3 * kOriginBits + 3;

private:
    void sort_keys(size_t n);
};

/// The kOriginBits low bits of x spread to every third bit (bit k to bit 3k).
constexpr uint32_t spread_bits3(uint32_t x) {
    x &= 0x3FFu;
    x = (x | (x << 16)) & 0x030000FFu;
    x = (x | (x << 8)) & 0x0300F00Fu;
    x = (x | (x << 4)) & 0x030C30C3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

/// floor(x) for x in [0, 2^kOriginBits), else 0 or 2^kOriginBits - 1; 0 for NaN (a float's
/// conversion to an integer out of range is undefined). Selects, no branch: the keys of
/// incoherent rays would mispredict every one.
inline uint32_t quantise_origin(float x) {
    constexpr float kTop = float((1 << RayOrder::kOriginBits) - 1);
    x = x > 0.0f ? x : 0.0f;  // maxss: NaN becomes 0
    x = x < kTop ? x : kTop;  // minss
    return uint32_t(int32_t(x));
}

/// x, or +inf (lowest) / -inf (highest) when it is an infinity or a NaN: the bounds of the finite values.
inline float lowest_finite(float x) { return std::fabs(x) <= 3.402823466e+38f ? x : INFINITY; }
inline float highest_finite(float x) { return std::fabs(x) <= 3.402823466e+38f ? x : -INFINITY; }

/// spread_bits3 of every quantised coordinate: one load instead of a dozen operations.
inline constexpr auto kSpreadOrigin = [] {
    std::array<uint32_t, 1 << RayOrder::kOriginBits> table{};
    for (uint32_t i = 0; i < table.size(); ++i) table[i] = spread_bits3(i);
    return table;
}();

template <class RayAt>
void RayOrder::sort(size_t n, RayAt&& ray) {
    // Six independent chains of minss/maxss in registers (an array here went through memory).
    float lx = INFINITY, ly = INFINITY, lz = INFINITY, hx = -INFINITY, hy = -INFINITY, hz = -INFINITY;
    for (size_t i = 0; i < n; ++i) {
        Vec3 org, dir;
        ray(i, org, dir);
        float x = lowest_finite(org.x), y = lowest_finite(org.y), z = lowest_finite(org.z);
        lx = x < lx ? x : lx, ly = y < ly ? y : ly, lz = z < lz ? z : lz;
        x = highest_finite(org.x), y = highest_finite(org.y), z = highest_finite(org.z);
        hx = hx < x ? x : hx, hy = hy < y ? y : hy, hz = hz < z ? z : hz;
    }
    float lo[3] = {lx, ly, lz}, scale[3];
    const float hi[3] = {hx, hy, hz};
    for (int a = 0; a < 3; ++a) {
        const float extent = hi[a] - lo[a];  // -inf without a finite origin, +inf past the float range
        scale[a] = extent > 0.0f && extent <= 3.402823466e+38f ? float(1 << kOriginBits) / extent : 0.0f;
        if (!(extent > 0.0f)) lo[a] = 0.0f;
    }
    keys.resize(n);
    for (size_t i = 0; i < n; ++i) {
        Vec3 org, dir;
        ray(i, org, dir);
        const uint32_t octant = uint32_t(dir.x < 0.0f) | uint32_t(dir.y < 0.0f) << 1 | uint32_t(dir.z < 0.0f) << 2;
        const uint32_t morton = kSpreadOrigin[quantise_origin((org.x - lo[0]) * scale[0])] |
                                kSpreadOrigin[quantise_origin((org.y - lo[1]) * scale[1])] << 1 |
                                kSpreadOrigin[quantise_origin((org.z - lo[2]) * scale[2])] << 2;
        keys[i] = octant << (3 * kOriginBits) | morton;
    }
    sort_keys(n);
}

}  // namespace thicket
