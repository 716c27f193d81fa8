#pragma once
/// The one exception type of the library: its message names the file, line, option or value at fault.
#include <stdexcept>
#include <string>

namespace thicket {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace thicket
