#include <iostream>

#include "cli.h"
#include "core/memory.h"
#include "native/native_model.h"

int main(int argc, char** argv) {
  kfw::retain_freed_memory();
  // KFW_NATIVE=1: model expressions compiled by the system's C compiler (native/native_model.h).
  if (const std::string notice = kfw::native::enable_from_environment(); !notice.empty())
    std::cerr << "kfw-cli: notice: " << notice << "\n";
  std::vector<std::string> args(argv + 1, argv + argc);
  return kfw::run_cli(args, std::cout, std::cerr);
}
