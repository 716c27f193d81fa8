// The unit test program's operator new and delete: malloc and free, counting each new on the
// calling thread. Every non-aligned form is replaced together (the aligned ones are left to the
// runtime, which pairs them itself): under AddressSanitizer, which supplies its own operator new,
// a block from one family freed by the other would be reported as a mismatch.
#include "allocation_counter.h"

#include <cstdlib>
#include <new>

namespace {

// Plain thread_local integers: no constructor or destructor to run inside operator new.
thread_local uint64_t t_blocks = 0;
thread_local uint64_t t_bytes = 0;

void* counted_malloc(std::size_t size) noexcept {
    ++t_blocks;
    t_bytes += size;
    return std::malloc(size == 0 ? 1 : size);
}

void* counted_new(std::size_t size) {
    for (;;) {
        if (void* p = counted_malloc(size)) return p;
        // As the standard's operator new: ask the new-handler to free memory, else throw.
        const std::new_handler handler = std::get_new_handler();
        if (!handler) throw std::bad_alloc();
        handler();
    }
}

}  // namespace

namespace thicket::test {
Allocations allocations_on_this_thread() { return {t_blocks, t_bytes}; }
}  // namespace thicket::test

void* operator new(std::size_t size) { return counted_new(size); }
void* operator new[](std::size_t size) { return counted_new(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return counted_malloc(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return counted_malloc(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
