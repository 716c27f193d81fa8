#pragma once
/// Mailboxing (Amanatides & Woo 1987): a primitive referenced by several cells (octree, kD-tree,
/// BSP fragments) is tested at most once per query. Const structures are queried from many threads
/// at once, so the stamps live with the thread. Each thread keeps one stamp per primitive and a query counter that only
/// grows, so a stamp left by any earlier query (of any structure on this thread) never equals
/// the current query's: nothing needs clearing between queries or structures.
#include <algorithm>
#include <cstdint>
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

}  // namespace thicket
