// Runs kfw-cli (KFW_CLI) and captures its output and exit code, for CLI tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include "common/time_scale.h"

namespace kfw::testing {

struct CliOutput {
  int code = -1;
  std::string text;  // stdout + stderr
};

// Runs a shell command line and reads what it prints.
inline CliOutput run_command(const std::string& cmd) {
  CliOutput o;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return o;
  std::array<char, 4096> buf{};
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0)
    o.text.append(buf.data(), n);
  const int status = pclose(p);
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

#ifdef KFW_CLI
// kfw-cli ARGS; `redirect` picks what is read: stdout and stderr by default, "2>/dev/null"
// stdout only.
inline CliOutput cli(const std::string& args, const std::string& redirect = "2>&1") {
  return run_command(std::string(KFW_CLI) + " " + args + " " + redirect);
}
#endif

}  // namespace kfw::testing
