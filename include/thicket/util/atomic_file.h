#pragma once
/// Replacing a file all at once: outputs are written under a temporary name in the same
/// directory, then renamed over the target, so a failed run never leaves a partial file behind.
#include <functional>
#include <string>
#include <string_view>

namespace thicket {

/// Calls write(temp) with a fresh temporary path next to `path`, then renames it to `path`. If
/// write throws or the rename fails, the temporary file is removed, `path` is left as it was, and
/// the exception is rethrown; a thicket::Error's message then names `path` instead of the
/// temporary name.
void write_atomically(const std::string& path, const std::function<void(const std::string& temp)>& write);

/// Writes `bytes` to `path` through write_atomically(); Error "<path>: cannot write: <reason>".
void write_file_atomically(const std::string& path, std::string_view bytes);

}  // namespace thicket
