// kfw-cli: simulate, run, gain and list from the command line, without Qt.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace kfw {

// Returns the process exit code; errors go to `err` as one line.
int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace kfw
