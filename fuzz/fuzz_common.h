#pragma once
// Shared by the harnesses: a private scratch directory on tmpfs for the readers that take a
// path, and the rule every harness enforces: thicket::Error is the only way a reader may refuse
// an input; anything else (a crash, a sanitizer report, another exception) is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

namespace thicket::fuzz {

/// A directory of this process's own (tmpfs when there is one), made on first use.
inline const std::string& scratch_dir() {
    static const std::string dir = [] {
        std::error_code ec;
        const std::filesystem::path base = std::filesystem::exists("/dev/shm", ec) ? "/dev/shm" : std::filesystem::temp_directory_path();
        const std::filesystem::path d = base / ("thicket-fuzz-" + std::to_string(long(::getpid())));
        std::filesystem::create_directories(d, ec);
        // Removed at a normal exit; after a crash it stays, with the files the input produced.
        // The path is kept in a string that is never destroyed: the handler runs after statics die.
        static const std::string* const removed_at_exit = new std::string(d.string());
        std::atexit([] {
            std::error_code ignored;
            std::filesystem::remove_all(*removed_at_exit, ignored);
        });
        return d.string();
    }();
    return dir;
}

/// Writes `bytes` to `name` in the scratch directory; returns its path.
inline std::string scratch_file(const std::string& name, std::string_view bytes) {
    const std::string path = scratch_dir() + "/" + name;
    if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fwrite(bytes.data(), 1, bytes.size(), f);
        std::fclose(f);
    }
    return path;
}

inline std::string_view as_text(const uint8_t* data, size_t size) {
    return {reinterpret_cast<const char*>(data), size};
}

}  // namespace thicket::fuzz
