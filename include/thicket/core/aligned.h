#pragma once
/// std::vector allocator with a fixed alignment, for node pools that must start on a cache line.
#include <cstddef>
#include <new>
#include <vector>

namespace thicket {

template <class T, std::size_t Align>
struct AlignedAllocator {
    using value_type = T;
    template <class U>
    struct rebind {
        using other = AlignedAllocator<U, Align>;
    };
    AlignedAllocator() = default;
    template <class U>
    AlignedAllocator(const AlignedAllocator<U, Align>&) {}
    T* allocate(std::size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(Align))); }
    void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(Align)); }
    template <class U>
    bool operator==(const AlignedAllocator<U, Align>&) const { return true; }
};

template <class T, std::size_t Align = 64>
using AlignedVector = std::vector<T, AlignedAllocator<T, Align>>;

}  // namespace thicket
