// Reordered batches: the block size and the radix sort of a block's keys (accel/ray_order.h).
#include "thicket/accel/ray_order.h"

#include <algorithm>
#include <array>

namespace thicket {

size_t reorder_block(size_t count, unsigned workers) {
    const size_t per_worker = count / (2 * size_t(std::max(workers, 1u)));
    const size_t block = std::clamp<size_t>(per_worker, kReorderMin, kReorderBlock);
    return block / 256 * 256;
}

void RayOrder::sort_keys(size_t n) {
    // Least significant digit first, kKeyBits in passes of at most 11 bits (a histogram of 8 KiB
    // stays in the L1 cache): stable counting sorts, each key travelling with its index in one
    // 64-bit word; the first pass reads the keys themselves.
    constexpr int kPasses = (kKeyBits + 10) / 11, kDigitBits = (kKeyBits + kPasses - 1) / kPasses;
    constexpr uint32_t kBuckets = 1u << kDigitBits;
    pairs.resize(n);
    scratch.resize(n);
    std::array<std::array<uint32_t, kBuckets>, kPasses> count{};
    for (size_t i = 0; i < n; ++i)
        for (int p = 0; p < kPasses; ++p) ++count[p][(keys[i] >> (kDigitBits * p)) & (kBuckets - 1)];
    for (auto& histogram : count) {
        uint32_t sum = 0;
        for (uint32_t& c : histogram) {
            const uint32_t here = c;
            c = sum;
            sum += here;
        }
    }
    for (size_t i = 0; i < n; ++i) pairs[count[0][keys[i] & (kBuckets - 1)]++] = uint64_t(keys[i]) << 32 | uint32_t(i);
    for (int p = 1; p < kPasses; ++p) {
        const int shift = 32 + kDigitBits * p;
        for (size_t i = 0; i < n; ++i) scratch[count[p][(pairs[i] >> shift) & (kBuckets - 1)]++] = pairs[i];
        pairs.swap(scratch);
    }
    order.resize(n);
    for (size_t i = 0; i < n; ++i) order[i] = uint32_t(pairs[i]);
}

}  // namespace thicket
