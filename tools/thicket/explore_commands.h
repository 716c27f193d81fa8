#pragma once
// `thicket explore` and `thicket explain` (cmd_explore.cpp; the server is in explore/).
#include "common.h"

namespace thicket::cli {

Command add_explore_command(CLI::App& app);
Command add_explain_command(CLI::App& app);

}  // namespace thicket::cli
