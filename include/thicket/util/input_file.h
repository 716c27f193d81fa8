#pragma once
/// Reading inputs safely. Every reader goes through these, so that a device (/dev/zero), a FIFO
/// or a file bigger than memory is refused with a message naming the file and the size, instead
/// of an endless read or std::bad_alloc.
#include <cstdint>
#include <string>

namespace thicket {

/// Throws Error "<path>: no such file", "<path>: is a directory, not a <kind>" or "<path>: is not a
/// regular file (a character device): thicket reads <kind>s only from regular files". Returns the
/// file's size in bytes.
uint64_t check_regular_input(const std::string& path, const char* kind);

/// Reads the whole regular file `path` (check_regular_input(), then check_memory() for its size).
std::string read_input_file(const std::string& path, const char* kind);

/// Bytes of memory this process may still allocate: MemAvailable of /proc/meminfo (physical memory
/// when that is unknown), capped by RLIMIT_AS.
uint64_t available_memory();

/// Throws Error "<what> needs <bytes> of memory, but only <available> is available" when `bytes`
/// exceeds available_memory(). Call it before allocating what an input asks for.
void check_memory(uint64_t bytes, const std::string& what);

/// "1.5 GiB" style sizes for these messages.
std::string memory_text(uint64_t bytes);

}  // namespace thicket
