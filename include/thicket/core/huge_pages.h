#pragma once
/// Large arrays on 2 MiB pages. A build touches hundreds of MB of fresh memory (the dragon, 871k
/// triangles: boxes, centroids, the node pool, the blocks), and on 4 KiB pages each first touch
/// is a page fault; on the virtualized machines measured a fault costs microseconds, a quarter of
/// bvh8's build time on the dragon. Transparent huge pages in `madvise` mode (Debian's default)
/// give 2 MiB pages only to memory that asks for them. (AlignedAllocator advises its big arrays
/// itself; reserve_huge is for the std::vectors of a build.)
#include <cstddef>
#include <vector>

namespace thicket {

/// Asks the kernel to back the 2 MiB-aligned part of [p, p + bytes) with huge pages when it is
/// first touched. A hint: nothing happens without transparent huge pages, below 2 MiB, or
/// off Linux. Call before the memory is first written.
void advise_huge_pages(const void* p, size_t bytes);

/// v.reserve(n), the new memory advised for huge pages before anything touches it; then resize
/// or fill v as usual. (A vector that already had room for n keeps its memory unadvised.)
template <class Vector>
void reserve_huge(Vector& v, size_t n) {
    if (v.capacity() >= n) return;
    v.reserve(n);
    advise_huge_pages(v.data(), v.capacity() * sizeof(typename Vector::value_type));
}

/// A private anonymous mapping on 2 MiB pages: `start` is 2 MiB-aligned and `length` a multiple
/// of 2 MiB. An empty one (start null) when the system refuses it.
struct HugeMapping {
    void* start = nullptr;
    size_t length = 0;
};

/// A mapping of at least `bytes`, advised for huge pages: one released earlier with the same
/// length when the pool has it (its pages already faulted in: a loop over batches asks for the
/// same sizes every call, and the kernel zeroes a fresh 2 MiB page at ~5-10 GB/s), else a fresh
/// one. Its contents are undefined. Thread-safe. Off Linux, or without MADV_HUGEPAGE, always empty.
HugeMapping take_huge_mapping(size_t bytes);

/// Hands a mapping from take_huge_mapping back: kept for the next take of the same length while
/// the pool holds at most kHugePoolBytes, else unmapped. Thread-safe.
void release_huge_mapping(const HugeMapping& mapping);
inline constexpr size_t kHugePoolBytes = size_t(256) << 20;

}  // namespace thicket
