// kfw-cli's long jobs (run --seeds, sweep, tune): SIGINT and SIGTERM ask the engine to stop (it
// polls the flag between runs), and the command then writes no --out and exits 130 or 143
// (../shared/STAGE.md; parts of other shards already written stay). Progress goes to stderr when
// it is a terminal (one line redrawn) or --progress forces it (a line every 10 %, for CI logs).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>

namespace kfw {

class CliJob {
 public:
  // Installs the handlers until destruction. `what`: "seeds", "points", "evaluations".
  CliJob(std::ostream& err, bool force_progress, std::string what);
  ~CliJob();
  CliJob(const CliJob&) = delete;
  CliJob& operator=(const CliJob&) = delete;

  const std::atomic<bool>* cancel() const;
  // 130 after SIGINT, 143 after SIGTERM; 0 when no signal came.
  int interrupted() const;
  // "kfw-cli: interrupted by SIGINT after 12 of 40 seeds; nothing written", for the caller.
  std::string interrupted_message() const;
  // From any thread: `done` of `total` (total 0: unknown), with an optional note ("best 1.23").
  void progress(std::size_t done, std::size_t total, const std::string& note = "");
  // Ends the progress line (a terminal's line is finished with a newline).
  void finish();

 private:
  std::ostream& err_;
  bool enabled_ = false, tty_ = false;
  std::string what_;
  std::atomic<std::size_t> done_{0}, total_{0};
  std::atomic<int> last_decile_{-1};
  std::atomic<long long> last_ms_{0};
  std::chrono::steady_clock::time_point start_;
  bool drew_ = false;
};

}  // namespace kfw
