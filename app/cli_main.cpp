#include <iostream>

#include "cli.h"
#include "core/memory.h"

int main(int argc, char** argv) {
  kfw::retain_freed_memory();
  std::vector<std::string> args(argv + 1, argv + argc);
  return kfw::run_cli(args, std::cout, std::cerr);
}
