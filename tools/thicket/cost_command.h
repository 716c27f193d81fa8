#pragma once
// `thicket cost` (cmd_cost.cpp).
#include "common.h"

namespace thicket::cli {

/// Registers `thicket cost`: analytic and counted intersection tests of the `spheres` scene.
Command add_cost_command(CLI::App& app);

}  // namespace thicket::cli
