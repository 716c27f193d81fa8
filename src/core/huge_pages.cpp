#include "thicket/core/huge_pages.h"

#include <cstdint>
#include <mutex>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace thicket {

void advise_huge_pages(const void* p, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr uintptr_t kHuge = uintptr_t(2) << 20;
    const uintptr_t first = (reinterpret_cast<uintptr_t>(p) + kHuge - 1) / kHuge * kHuge;
    const uintptr_t last = (reinterpret_cast<uintptr_t>(p) + bytes) / kHuge * kHuge;
    // Failure (no THP, memory not anonymous) leaves 4 KiB pages, which work as before.
    if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

#if defined(__linux__) && defined(MADV_HUGEPAGE)
namespace {

constexpr size_t kHugePage = size_t(2) << 20;

/// Released mappings kept for the next take of the same length, and their bytes.
struct HugePool {
    std::mutex mutex;
    std::vector<HugeMapping> kept;
    size_t bytes = 0;
};

HugePool& huge_pool() {
    static HugePool pool;
    return pool;
}

/// A fresh mapping of `length` bytes (a multiple of kHugePage), 2 MiB-aligned and advised for
/// huge pages; null if the system refuses it.
void* map_huge(size_t length) {
    // One page more than needed, so that a 2 MiB-aligned start lies inside; the rest is returned.
    const size_t span = length + kHugePage;
    void* raw = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) return nullptr;
    const uintptr_t start = (reinterpret_cast<uintptr_t>(raw) + kHugePage - 1) / kHugePage * kHugePage;
    const size_t head = start - reinterpret_cast<uintptr_t>(raw);
    if (head) munmap(raw, head);
    if (span - head - length) munmap(reinterpret_cast<char*>(start) + length, span - head - length);
    madvise(reinterpret_cast<void*>(start), length, MADV_HUGEPAGE);  // a hint: ignored without THP
    return reinterpret_cast<void*>(start);
}

}  // namespace

HugeMapping take_huge_mapping(size_t bytes) {
    const size_t length = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    if (length < bytes || length == 0) return {};  // overflow, or nothing asked
    {
        HugePool& pool = huge_pool();
        const std::lock_guard<std::mutex> lock(pool.mutex);
        for (size_t i = 0; i < pool.kept.size(); ++i)
            if (pool.kept[i].length == length) {
                const HugeMapping m = pool.kept[i];
                pool.bytes -= length;
                pool.kept.erase(pool.kept.begin() + std::ptrdiff_t(i));
                return m;
            }
    }
    void* start = map_huge(length);
    return start ? HugeMapping{start, length} : HugeMapping{};
}

void release_huge_mapping(const HugeMapping& mapping) {
    if (!mapping.start) return;
    {
        HugePool& pool = huge_pool();
        const std::lock_guard<std::mutex> lock(pool.mutex);
        if (pool.bytes + mapping.length <= kHugePoolBytes) {
            pool.kept.push_back(mapping);
            pool.bytes += mapping.length;
            return;
        }
    }
    munmap(mapping.start, mapping.length);
}
#else
HugeMapping take_huge_mapping(size_t) { return {}; }
void release_huge_mapping(const HugeMapping&) {}
#endif

}  // namespace thicket
