#include "thicket/kdtree/mailbox.h"

#include <algorithm>
#include <atomic>
#include <vector>

namespace thicket {

namespace {

struct Slot {
    uint64_t owner = 0;
    uint64_t last_use = 0;
    uint32_t query = 0;
    std::vector<uint32_t> stamps;
};

/// Four structures per thread: enough for a structure and the one it is compared with, without
/// letting a thread that touches many structures keep a stamp array for each.
struct ThreadMailboxes {
    Slot slots[4];
    uint64_t clock = 0;
};

thread_local ThreadMailboxes tls;

}  // namespace

uint64_t new_mailbox_owner() {
    static std::atomic<uint64_t> next{1};
    return next.fetch_add(1, std::memory_order_relaxed);
}

Mailbox::Mailbox(uint64_t owner, size_t primitives) {
    ThreadMailboxes& t = tls;
    Slot* slot = nullptr;
    for (Slot& s : t.slots)
        if (s.owner == owner && s.stamps.size() == primitives) slot = &s;
    if (!slot) {
        slot = std::min_element(std::begin(t.slots), std::end(t.slots),
                                [](const Slot& a, const Slot& b) { return a.last_use < b.last_use; });
        slot->owner = owner;
        slot->query = 0;
        slot->stamps.assign(primitives, 0);
    }
    slot->last_use = ++t.clock;
    if (++slot->query == 0) {  // the counter wrapped: old stamps could match again
        std::fill(slot->stamps.begin(), slot->stamps.end(), 0u);
        slot->query = 1;
    }
    stamps_ = slot->stamps.data();
    query_ = slot->query;
}

}  // namespace thicket
