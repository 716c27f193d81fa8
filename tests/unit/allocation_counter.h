#pragma once
/// Counted work for tests that assert how a loader's cost grows with its input: the blocks and
/// bytes that operator new hands out on the calling thread (allocation_counter.cpp replaces the
/// global operator new and delete of the unit test program for this). Unlike a clock, the
/// counts do not depend on the machine's load: the same input always allocates the same.
#include <cstdint>

namespace thicket::test {

struct Allocations {
    uint64_t blocks = 0;
    uint64_t bytes = 0;
};

/// What operator new has handed out on this thread since it started.
Allocations allocations_on_this_thread();

/// Allocations on this thread while `f` runs.
template <class F>
Allocations count_allocations(F&& f) {
    const Allocations before = allocations_on_this_thread();
    f();
    const Allocations after = allocations_on_this_thread();
    return {after.blocks - before.blocks, after.bytes - before.bytes};
}

}  // namespace thicket::test
