#include "thicket/util/input_file.h"

#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>

#include "thicket/core/error.h"

namespace thicket {

namespace {

const char* file_type_name(mode_t mode) {
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

}  // namespace

uint64_t check_regular_input(const std::string& path, const char* kind) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) {
        if (errno == ENOENT) throw FileError(path + ": no such file");
        throw FileError(path + ": cannot read: " + std::strerror(errno));
    }
    if (S_ISDIR(st.st_mode)) throw FileError(path + ": is a directory, not a " + kind);
    // A device or FIFO has no size to check against memory, and /dev/zero never ends.
    if (!S_ISREG(st.st_mode))
        throw FileError(path + ": is " + file_type_name(st.st_mode) + ", not a regular file: thicket reads a " + kind +
                    " only from a regular file");
    return uint64_t(st.st_size);
}

std::string memory_text(uint64_t bytes) {
    static const char* const units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 6) {
        v /= 1024.0;
        ++u;
    }
    char buf[48];
    if (u == 0)
        std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(bytes));
    else
        std::snprintf(buf, sizeof buf, "%.1f %s", v, units[u]);
    return buf;
}

uint64_t available_memory() {
    // Read at most once a second: /proc/meminfo is generated on each read, and a reader of many
    // small files (or a fuzzer) would spend most of its time there.
    static std::mutex mutex;
    static std::chrono::steady_clock::time_point read_at;
    static uint64_t cached = 0;
    const std::lock_guard<std::mutex> lock(mutex);
    const auto now = std::chrono::steady_clock::now();
    if (cached != 0 && now - read_at < std::chrono::seconds(1)) return cached;
    read_at = now;
    uint64_t avail = 0;
    if (std::FILE* f = std::fopen("/proc/meminfo", "r")) {
        char line[256];
        while (std::fgets(line, sizeof line, f)) {
            unsigned long long kib = 0;
            if (std::sscanf(line, "MemAvailable: %llu kB", &kib) == 1) {
                avail = uint64_t(kib) * 1024;
                break;
            }
        }
        std::fclose(f);
    }
    if (avail == 0) {
        const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
        if (pages > 0 && page > 0) avail = uint64_t(pages) * uint64_t(page);
    }
    if (avail == 0) avail = uint64_t(1) << 40;  // unknown: no check beyond what the allocator says
    struct rlimit lim {};
    if (::getrlimit(RLIMIT_AS, &lim) == 0 && lim.rlim_cur != RLIM_INFINITY && uint64_t(lim.rlim_cur) < avail)
        avail = uint64_t(lim.rlim_cur);
    cached = avail;
    return avail;
}

void check_memory(uint64_t bytes, const std::string& what) {
    const uint64_t avail = available_memory();
    if (bytes > avail)
        throw Error(what + " needs " + memory_text(bytes) + " of memory, but only " + memory_text(avail) +
                    " is available");
}

std::string read_input_file(const std::string& path, const char* kind) {
    const uint64_t size = check_regular_input(path, kind);
    check_memory(size, path + ": reading this " + std::to_string(size) + "-byte file");
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!f) throw FileError(path + ": cannot open: " + std::strerror(errno));
    std::string bytes(size_t(size), '\0');
    const size_t got = std::fread(bytes.data(), 1, bytes.size(), f.get());
    if (std::ferror(f.get())) throw FileError(path + ": read error");
    // A file that shrank while being read is read as it now is; one that grew is read up to the
    // size checked above (the rest is not ours to trust).
    bytes.resize(got);
    return bytes;
}

}  // namespace thicket
