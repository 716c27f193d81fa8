#pragma once
// The tetra structure's load-time checks (validate.cpp: structure, validate_geometry.cpp: what the
// walk relies on) refuse a file with one message form.
#include <string>

#include "thicket/core/error.h"

namespace thicket {

/// Throws Error("invalid tetra structure: " + what).
[[noreturn]] inline void invalid_tetra(const std::string& what) { throw Error("invalid tetra structure: " + what); }

}  // namespace thicket
