#include "thicket/util/atomic_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

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

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

/// Names of an already open stream: their "targets" (pipe:[123]) are not paths to rename over.
bool is_descriptor_path(const std::string& p) {
    return p == "/dev/stdout" || p == "/dev/stderr" || starts_with(p, "/dev/fd/") || starts_with(p, "/proc/self/fd/");
}

}  // namespace

OutputTarget resolve_output(const std::string& path) {
    namespace fs = std::filesystem;
    if (path.empty()) throw Error("empty output file name");
    if (path == "-") return {OutputTarget::Special, "/dev/stdout"};
    if (is_descriptor_path(path)) return {OutputTarget::Special, path};
    // Follow symlinks by hand: the link stays, its target is what gets written (and may not
    // exist yet, which std::filesystem::canonical would refuse).
    fs::path p(path);
    for (int hops = 0;; ++hops) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(p, ec))) break;
        if (hops == 40) throw Error(path + ": too many levels of symbolic links");
        const fs::path target = fs::read_symlink(p, ec);
        if (ec) throw Error(path + ": cannot read the symbolic link: " + ec.message());
        p = target.is_absolute() ? target : p.parent_path() / target;
        if (is_descriptor_path(p.string())) return {OutputTarget::Special, p.string()};
    }
    struct stat st {};
    if (::stat(p.c_str(), &st) != 0) {
        // Not there (or under a path that is not a directory): a new file, whose write reports it.
        if (errno != ENOENT && errno != ENOTDIR) throw Error(path + ": cannot write: " + std::strerror(errno));
        return {OutputTarget::New, p.string()};
    }
    if (S_ISDIR(st.st_mode)) throw Error(path + ": is a directory");
    if (!S_ISREG(st.st_mode)) return {OutputTarget::Special, p.string()};
    // Root may write anything, so access() cannot tell: a file nobody may write is kept as it is.
    if ((st.st_mode & 0222) == 0 || ::access(p.c_str(), W_OK) != 0)
        throw Error(path + ": is read-only; thicket does not replace it (make it writable or remove it first)");
    return {OutputTarget::Regular, p.string()};
}

void write_atomically(const std::string& path, const std::function<void(const std::string& temp)>& write) {
    const OutputTarget target = resolve_output(path);
    if (target.kind == OutputTarget::Special) {
        // Written through: a device or pipe cannot be replaced, and must not be.
        try {
            write(target.path);
        } catch (const FileError& e) {
            throw FileError(replace_all(e.what(), target.path, path));
        } catch (const Error& e) {
            throw Error(replace_all(e.what(), target.path, path));
        }
        return;
    }
    const std::string temp = temp_name_for(target.path);
    try {
        write(temp);
    } catch (const FileError& e) {
        // The message names the user's path, not the temporary; the kind (OSError in Python) stays.
        std::remove(temp.c_str());
        throw FileError(replace_all(e.what(), temp, path));
    } catch (const Error& e) {
        std::remove(temp.c_str());
        throw Error(replace_all(e.what(), temp, path));
    } catch (...) {
        std::remove(temp.c_str());
        throw;
    }
    struct stat old {};
    if (target.kind == OutputTarget::Regular && ::stat(target.path.c_str(), &old) == 0)
        ::chmod(temp.c_str(), old.st_mode & 07777);  // replacing keeps the file's permissions
    if (std::rename(temp.c_str(), target.path.c_str()) != 0) {
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
