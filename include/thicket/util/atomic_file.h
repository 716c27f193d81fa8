#pragma once
/// Writing outputs without clobbering what is not ours to replace. A regular file (or a new path)
/// is written under a temporary name in the same directory, then renamed over the target, so a
/// failed run never leaves a partial file behind. A special file (/dev/null, a FIFO, a terminal,
/// stdout as "-" or /dev/fd/N) is written through, never replaced; a symlink's target is written,
/// the link is kept; a read-only file or a directory is refused.
#include <functional>
#include <string>
#include <string_view>

namespace thicket {

/// What a write to `path` will do; see resolve_output().
struct OutputTarget {
    enum Kind { New, Regular, Special } kind = New;
    std::string path;  ///< where the bytes go: symlinks resolved; "-" becomes /dev/stdout
};

/// Classifies `path`: Special for "-", /dev/stdout, /dev/fd/N and anything that exists and is
/// neither a regular file nor a directory; Regular for an existing regular file; New otherwise.
/// Throws Error "<path>: ..." for a directory, a read-only regular file, a symlink loop, or a path
/// whose directory does not exist.
OutputTarget resolve_output(const std::string& path);

/// Calls write(p) and makes its result appear at `path`: for a special file p is the file itself;
/// otherwise p is a fresh temporary path next to the (symlink-resolved) target, renamed over it
/// afterwards (keeping an existing file's permissions). If write throws or the rename fails, the
/// temporary file is removed, `path` is left as it was, and the exception is rethrown; a
/// thicket::Error's message then names `path` instead of the temporary name.
void write_atomically(const std::string& path, const std::function<void(const std::string& temp)>& write);

/// Writes `bytes` to `path` through write_atomically(); Error "<path>: cannot write: <reason>".
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace thicket
