#pragma once
// `thicket occupancy` (cmd_closest.cpp, beside `thicket closest`: both answer points).
#include "common.h"

namespace thicket::cli {

Command add_occupancy_command(CLI::App& app);

}  // namespace thicket::cli
