// Linear BVH builder (Lauterbach et al. 2009; Karras 2012): primitives sorted once along a Morton
// curve (21 bits per axis of the centroid in the scene's centroid box), then every node is split
// where the highest bit in which its first and last codes differ changes: the hierarchy of
// Karras's radix tree, found top-down by binary search. No SAH is evaluated: the fastest build,
// at the price of looser trees (BENCHMARKS.md gives the trace-speed price).
#include <array>
#include <bit>
#include <vector>

#include "splitter.h"

namespace thicket::bvh_build {
namespace {

constexpr int kBitsPerAxis = 21;

/// The 21 low bits of v spread to every third bit (bit i to bit 3i).
uint64_t spread_bits(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffull;
    v = (v | v << 16) & 0x1f0000ff0000ffull;
    v = (v | v << 8) & 0x100f00f00f00f00full;
    v = (v | v << 4) & 0x10c30c30c30c30c3ull;
    v = (v | v << 2) & 0x1249249249249249ull;
    return v;
}

/// Axis whose coordinate bit sits at code bit `bit` (x on 3i+2, y on 3i+1, z on 3i).
int axis_of_bit(int bit) { return 2 - bit % 3; }

class LbvhSplitter final : public Splitter {
public:
    explicit LbvhSplitter(BuildContext& ctx) : Splitter(ctx) {
        const uint32_t n = uint32_t(ctx.indices.size());
        const auto& c = ctx.prims.centroids;
        Aabb box;
        for (uint32_t i = 0; i < n; ++i) box.grow(c[i]);
        Vec3 scale;
        for (int a = 0; a < 3; ++a) {
            const float extent = box.max[a] - box.min[a];
            scale[a] = extent > 0.0f ? float((1u << kBitsPerAxis) - 1) / extent : 0.0f;
        }
        std::vector<uint64_t> codes(n);
        parallel_for(n, kMinChunk, ctx.options.threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                uint64_t code = 0;
                for (int a = 0; a < 3; ++a) {
                    const float f = (c[i][a] - box.min[a]) * scale[a];
                    // NaN and out-of-range coordinates clamp, never an invalid cast.
                    const uint64_t q = f > 0.0f ? uint64_t(std::min(f, float((1u << kBitsPerAxis) - 1))) : 0;
                    code |= spread_bits(q) << (2 - a);
                }
                codes[i] = code;
            }
        });
        sort_by_code(codes);
    }

    Split split(const NodeRange& node, unsigned) override {
        if (node.count <= uint32_t(ctx_.options.max_leaf)) return {};
        const uint64_t first = codes_[node.first], last = codes_[node.first + node.count - 1];
        if (first == last) return median_split(node);  // one Morton cell: split by count
        const int bit = 63 - std::countl_zero(first ^ last);
        // The first position whose code has `bit` set: codes are sorted and share the bits above.
        uint32_t lo = node.first, hi = node.first + node.count - 1;  // codes_[hi] has it, codes_[lo] not
        while (hi - lo > 1) {
            const uint32_t mid = lo + (hi - lo) / 2;
            ((codes_[mid] >> bit) & 1 ? hi : lo) = mid;
        }
        return plain_split(hi - node.first, axis_of_bit(bit));
    }

    /// Splits by count, keeping the Morton order (the codes travel with the indices).
    Split median_split(const NodeRange& node) override {
        const int bit = codes_[node.first] == codes_[node.first + node.count - 1]
                            ? 0
                            : 63 - std::countl_zero(codes_[node.first] ^ codes_[node.first + node.count - 1]);
        return plain_split(node.count / 2, axis_of_bit(bit));
    }

private:
    /// Sorts ctx_.indices (0..n-1 on entry) by code, ties by index (an LSD radix sort, stable),
    /// and keeps the sorted codes in codes_.
    void sort_by_code(const std::vector<uint64_t>& codes) {
        auto& idx = ctx_.indices;
        const size_t n = idx.size();
        std::vector<uint32_t> tmp(n);
        for (int shift = 0; shift < 3 * kBitsPerAxis; shift += 8) {
            std::array<size_t, 257> offset{};
            for (uint32_t i : idx) ++offset[((codes[i] >> shift) & 255) + 1];
            if (*std::max_element(offset.begin(), offset.end()) == n) continue;  // one digit: nothing moves
            for (size_t d = 1; d < offset.size(); ++d) offset[d] += offset[d - 1];
            for (uint32_t i : idx) tmp[offset[(codes[i] >> shift) & 255]++] = i;
            idx.swap(tmp);
        }
        codes_.resize(n);
        for (size_t k = 0; k < n; ++k) codes_[k] = codes[idx[k]];
    }

    std::vector<uint64_t> codes_;  ///< Morton code of the primitive at each index position
};

}  // namespace

std::unique_ptr<Splitter> make_lbvh_splitter(BuildContext& ctx) { return std::make_unique<LbvhSplitter>(ctx); }

}  // namespace thicket::bvh_build
