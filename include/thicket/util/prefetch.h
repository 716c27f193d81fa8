#pragma once
/// Asking for memory ahead of its use, for batches whose data is cold (tens of MB read once).
#include <cstddef>

namespace thicket {

/// Asks for every cache line of [p, p + bytes) at once, so that their misses overlap: a loop that
/// spends long on each element (a traversal per ray) leaves the hardware prefetcher behind, and
/// one that does little keeps only a few lines in flight.
inline void prefetch_range(const void* p, size_t bytes) {
    const char* first = static_cast<const char*>(p);
    for (const char* q = first; q < first + bytes; q += 64) __builtin_prefetch(q);
}

}  // namespace thicket
