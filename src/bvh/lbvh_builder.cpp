// Linear BVH builder (Lauterbach et al. 2009; Karras 2012): primitives sorted once along a Morton
// curve (21 bits per axis of the centroid in the scene's centroid box), then every node is split
// where the highest bit in which its first and last codes differ changes: the hierarchy of
// Karras's radix tree, found top-down by binary search. No SAH is evaluated: the fastest build,
// at the price of looser trees (BENCHMARKS.md gives the trace-speed price).
#include <bit>
#include <vector>

#include "morton.h"
#include "splitter.h"

namespace thicket::bvh_build {
namespace {

class LbvhSplitter final : public Splitter {
public:
    explicit LbvhSplitter(BuildContext& ctx) : Splitter(ctx) {
        codes_ = morton_sort(ctx.prims.centroids, ctx.options.threads, ctx.indices);
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
        return plain_split(hi - node.first, morton_axis_of_bit(bit));
    }

    /// Splits by count, keeping the Morton order (the codes travel with the indices).
    Split median_split(const NodeRange& node) override {
        const int bit = codes_[node.first] == codes_[node.first + node.count - 1]
                            ? 0
                            : 63 - std::countl_zero(codes_[node.first] ^ codes_[node.first + node.count - 1]);
        return plain_split(node.count / 2, morton_axis_of_bit(bit));
    }

private:
    std::vector<uint64_t> codes_;  ///< Morton code of the primitive at each index position
};

}  // namespace

std::unique_ptr<Splitter> make_lbvh_splitter(BuildContext& ctx) { return std::make_unique<LbvhSplitter>(ctx); }

}  // namespace thicket::bvh_build
