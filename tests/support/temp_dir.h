#pragma once
// A directory that exists for one test and is removed afterwards, for tests that write files.
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace thicket::testing {

class TempDir {
public:
    /// A fresh directory under the system's temporary directory, named by `prefix`, the process
    /// and a counter, so parallel test processes never share one.
    explicit TempDir(const std::string& prefix) {
        static int counter = 0;
        path_ = std::filesystem::temp_directory_path() /
                (prefix + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    /// Writes `bytes` to `name` (relative to the directory; its folders must exist) and returns its path.
    std::string file(const std::string& name, const std::string& bytes) const {
        const std::filesystem::path p = path_ / name;
        std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return p.string();
    }
    std::string dir() const { return path_.string(); }

private:
    std::filesystem::path path_;
};

}  // namespace thicket::testing
