#pragma once
/// A minimal parallel loop over an index range: std::thread workers pull fixed-size chunks from
/// one atomic counter, so uneven work (rays that hit deep geometry) balances itself.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

namespace thicket {

/// Number of workers for a `threads` request: the request itself, or the hardware's concurrency
/// (at least 1) when it is 0.
inline unsigned resolve_threads(unsigned threads) {
    if (threads != 0) return threads;
    const unsigned hw = std::thread::hardware_concurrency();
    return hw == 0 ? 1u : hw;
}

/// Calls f(begin, end) for disjoint chunks of at most `grain` indices that together cover
/// [0, count), on up to `threads` threads (0: all cores); the calling thread works too. Chunks
/// run in no particular order. If any call throws, no further chunks are started, every worker is
/// joined, and the first exception is rethrown to the caller.
template <class F>
void parallel_for(size_t count, size_t grain, unsigned threads, F&& f) {
    if (count == 0) return;
    grain = std::max<size_t>(grain, 1);
    const size_t chunks = (count + grain - 1) / grain;
    const size_t workers = std::min<size_t>(resolve_threads(threads), chunks);
    if (workers <= 1) {
        // No threads to start: keep exceptions and stack traces on the caller's thread.
        for (size_t begin = 0; begin < count; begin += grain) f(begin, std::min(count, begin + grain));
        return;
    }

    std::atomic<size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    std::mutex error_mutex;
    auto work = [&] {
        while (!failed.load(std::memory_order_relaxed)) {
            const size_t chunk = next.fetch_add(1, std::memory_order_relaxed);
            if (chunk >= chunks) return;
            const size_t begin = chunk * grain;
            try {
                f(begin, std::min(count, begin + grain));
            } catch (...) {
                std::lock_guard<std::mutex> lock(error_mutex);
                if (!error) error = std::current_exception();
                failed.store(true, std::memory_order_relaxed);
                return;
            }
        }
    };

    std::vector<std::thread> pool;
    pool.reserve(workers - 1);
    for (size_t i = 0; i + 1 < workers; ++i) {
        try {
            pool.emplace_back(work);
        } catch (const std::system_error&) {
            break;  // the system refused another thread: the ones we have still finish the loop
        }
    }
    work();
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

/// parallel_for whose workers each own a State (default-constructed once per worker): f(begin,
/// end, state) for every chunk, with the state of the worker running it, so that scratch memory
/// is allocated once per worker rather than once per chunk. The same exception rule.
template <class State, class F>
void parallel_for_with(size_t count, size_t grain, unsigned threads, F&& f) {
    if (count == 0) return;
    grain = std::max<size_t>(grain, 1);
    const size_t chunks = (count + grain - 1) / grain;
    const size_t workers = std::min<size_t>(resolve_threads(threads), chunks);
    std::atomic<size_t> next{0};
    parallel_for(workers, 1, unsigned(workers), [&](size_t, size_t) {
        State state;
        try {
            for (size_t chunk = next++; chunk < chunks; chunk = next++)
                f(chunk * grain, std::min(count, (chunk + 1) * grain), state);
        } catch (...) {
            next.store(chunks);  // the other workers start no further chunk
            throw;
        }
    });
}

}  // namespace thicket
