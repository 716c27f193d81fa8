#include "thicket/core/error.h"

#include <cstdio>

namespace thicket {

std::string format_number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

}  // namespace thicket
