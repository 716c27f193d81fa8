#include "thicket/util/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "thicket/core/error.h"

namespace thicket {

namespace {

std::string temp_name_for(const std::string& path) {
    // Unique per process and per call, so parallel writers of the same target never collide.
    static std::atomic<unsigned> counter{0};
    return path + ".tmp-" + std::to_string(long(getpid())) + "-" + std::to_string(counter.fetch_add(1));
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
    for (size_t pos = text.find(from); pos != std::string::npos; pos = text.find(from, pos + to.size()))
        text.replace(pos, from.size(), to);
    return text;
}

}  // namespace

void write_atomically(const std::string& path, const std::function<void(const std::string& temp)>& write) {
    const std::string temp = temp_name_for(path);
    try {
        write(temp);
    } catch (const Error& e) {
        std::remove(temp.c_str());
        throw Error(replace_all(e.what(), temp, path));
    } catch (...) {
        std::remove(temp.c_str());
        throw;
    }
    if (std::rename(temp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        std::remove(temp.c_str());
        throw FileError(path + ": cannot write: " + std::strerror(err));
    }
}

void write_file_atomically(const std::string& path, std::string_view bytes) {
    write_atomically(path, [&](const std::string& temp) {
        std::FILE* f = std::fopen(temp.c_str(), "wb");
        if (!f) throw FileError(path + ": cannot write: " + std::strerror(errno));
        const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
        const int write_err = errno;
        // fclose flushes: a full disk may only show up here.
        const bool closed = std::fclose(f) == 0;
        if (!ok || !closed) throw FileError(path + ": cannot write: " + std::strerror(ok ? errno : write_err));
    });
}

}  // namespace thicket
