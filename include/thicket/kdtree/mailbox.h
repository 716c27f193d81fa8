#pragma once
/// Mailboxing (Amanatides & Woo 1987) for structures that reference a primitive from several
/// cells: each query tests a primitive at most once. Const structures are queried from many
/// threads at once, so the mailboxes live with the threads: per thread and structure, a stamp
/// per primitive and a query counter; a primitive is tested only if its stamp is not the
/// current query's. Each thread keeps the mailboxes of its few most recently used structures.
#include <cstddef>
#include <cstdint>

namespace thicket {

/// A fresh identity for a structure's mailboxes (never reused, unlike addresses).
uint64_t new_mailbox_owner();

class Mailbox {
public:
    /// Starts a query on the calling thread's mailbox of structure `owner` over `primitives`
    /// primitives. Queries on one thread must not be nested.
    Mailbox(uint64_t owner, size_t primitives);

    /// True the first time `prim` is offered during this query.
    bool first_visit(uint32_t prim) {
        if (stamps_[prim] == query_) return false;
        stamps_[prim] = query_;
        return true;
    }

private:
    uint32_t* stamps_;
    uint32_t query_;
};

}  // namespace thicket
