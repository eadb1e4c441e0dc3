// Runs kfw-cli (KFW_CLI) and captures its output and exit code, for CLI tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace kfw::testing {

struct CliOutput {
  int code = -1;
  std::string text;  // stdout + stderr
};

inline CliOutput cli(const std::string& args) {
  const std::string cmd = std::string(KFW_CLI) + " " + args + " 2>&1";
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

}  // namespace kfw::testing
