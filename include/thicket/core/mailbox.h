#pragma once
/// Mailboxing (Amanatides & Woo 1987): a primitive referenced by several cells is tested at most
/// once per query. Two flavours share this header: Mailbox (octree, kD-tree, BSP fragments) and
/// RayMailbox (the grids).
///
/// Mailbox: const structures are queried from many threads at once, so the stamps live with the
/// thread. Each thread keeps one stamp per primitive and a query counter that only grows, so a
/// stamp left by any earlier query (of any structure on this thread) never equals the current
/// query's: nothing needs clearing between queries or structures.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace thicket {

class Mailbox {
public:
    /// Starts a query over primitives 0 .. count-1.
    explicit Mailbox(size_t count) : state_(thread_state()) {
        if (state_.stamps.size() < count) state_.stamps.resize(count, 0);
        if (++state_.query == 0) {  // the counter wrapped: forget every stamp
            std::fill(state_.stamps.begin(), state_.stamps.end(), 0u);
            state_.query = 1;
        }
        query_ = state_.query;
        stamps_ = state_.stamps.data();
    }

    /// True the first time primitive i is offered during this query.
    bool first_visit(uint32_t i) {
        if (stamps_[i] == query_) return false;
        stamps_[i] = query_;
        return true;
    }

private:
    struct State {
        std::vector<uint32_t> stamps;
        uint32_t query = 0;
    };
    static State& thread_state() {
        thread_local State state;
        return state;
    }

    State& state_;
    uint32_t query_ = 0;
    uint32_t* stamps_ = nullptr;
};

/// Per-ray mailboxing: a primitive referenced by several cells is tested once per ray. The
/// classic mailbox (each primitive stores the id of the last ray that tested it) is shared,
/// mutable state: with many threads it races, and the cache line ping-pongs between cores. This
/// one belongs to the ray: a small open-addressing hash set of the primitive ids tested so far,
/// held on the stack (64 slots), exact (it never forgets an id, so no primitive is tested twice),
/// and grown onto the heap in the rare ray that tests more than 48 distinct shared primitives.
///
/// Off (RayMailbox(false), the grids' `mailbox=off`), every offer is a first visit: one flag read
/// per offer instead of a second instantiation of each walk.
class RayMailbox {
public:
    explicit RayMailbox(bool on = true) : on_(on) {
        if (on_) std::memset(inline_, 0xFF, sizeof(inline_));
    }
    RayMailbox(const RayMailbox&) = delete;
    RayMailbox& operator=(const RayMailbox&) = delete;

    /// True the first time `id` is offered during this ray (the caller then tests it), false on
    /// every later offer. `id` must not be 0xFFFFFFFF.
    bool first_visit(uint32_t id) {
        if (!on_) return true;
        uint32_t h = slot_of(id);
        while (true) {
            const uint32_t s = slots_[h];
            if (s == id) return false;
            if (s == kEmpty) break;
            h = (h + 1) & mask_;
        }
        slots_[h] = id;
        if (++count_ * 4 > (mask_ + 1) * 3) grow();
        return true;
    }

    /// Slots in use (distinct ids offered); for tests.
    uint32_t size() const { return count_; }

private:
    static constexpr uint32_t kEmpty = 0xFFFFFFFFu;
    static constexpr uint32_t kInlineBits = 6;

    uint32_t slot_of(uint32_t id) const { return (id * 0x9E3779B1u) >> shift_; }  // Fibonacci hashing

    void grow() {
        const uint32_t old_size = mask_ + 1;
        std::unique_ptr<uint32_t[]> bigger(new uint32_t[old_size * 2]);
        std::memset(bigger.get(), 0xFF, sizeof(uint32_t) * old_size * 2);
        uint32_t* old = slots_;
        mask_ = old_size * 2 - 1;
        --shift_;
        slots_ = bigger.get();
        for (uint32_t i = 0; i < old_size; ++i) {
            if (old[i] == kEmpty) continue;
            uint32_t h = slot_of(old[i]);
            while (slots_[h] != kEmpty) h = (h + 1) & mask_;
            slots_[h] = old[i];
        }
        heap_ = std::move(bigger);  // frees the previous heap table, if any, after rehashing from it
    }

    bool on_;
    uint32_t* slots_ = inline_;
    uint32_t mask_ = (1u << kInlineBits) - 1;
    uint32_t shift_ = 32 - kInlineBits;
    uint32_t count_ = 0;
    std::unique_ptr<uint32_t[]> heap_;
    uint32_t inline_[1u << kInlineBits];
};

}  // namespace thicket
