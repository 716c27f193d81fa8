#pragma once
/// The one exception type of the library: its message names the file, line, option or value at fault.
#include <stdexcept>
#include <string>

namespace thicket {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// An Error about reaching a file (missing, a directory, unreadable, unwritable), as opposed to its
/// contents: bindings map it to their I/O error (Python's OSError), the CLI treats it like any Error.
class FileError : public Error {
public:
    using Error::Error;
};

/// x as the library's messages show a value: printf's %g (six significant digits).
std::string format_number(double x);

}  // namespace thicket
