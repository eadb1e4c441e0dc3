#include "cli_job.h"

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <mutex>

namespace kfw {

namespace {

std::atomic<bool> g_cancel{false};
std::atomic<int> g_signal{0};
struct sigaction g_old_int {
}, g_old_term{};
std::mutex g_draw;

extern "C" void on_signal(int sig) {
  g_signal.store(sig);
  g_cancel.store(true);
}

}  // namespace

CliJob::CliJob(std::ostream& err, bool force_progress, std::string what)
    : err_(err), what_(std::move(what)), start_(std::chrono::steady_clock::now()) {
  g_cancel.store(false);
  g_signal.store(0);
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;  // a second Ctrl-C ends the process at once
  ::sigaction(SIGINT, &sa, &g_old_int);
  ::sigaction(SIGTERM, &sa, &g_old_term);
  tty_ = ::isatty(STDERR_FILENO) == 1;
  enabled_ = force_progress || tty_;
}

CliJob::~CliJob() {
  finish();
  ::sigaction(SIGINT, &g_old_int, nullptr);
  ::sigaction(SIGTERM, &g_old_term, nullptr);
}

const std::atomic<bool>* CliJob::cancel() const {
  return &g_cancel;
}

int CliJob::interrupted() const {
  const int s = g_signal.load();
  return s == SIGINT ? 130 : s == SIGTERM ? 143 : 0;
}

std::string CliJob::interrupted_message() const {
  const int s = g_signal.load();
  std::string m = std::string("interrupted by ") + (s == SIGTERM ? "SIGTERM" : "SIGINT");
  const std::size_t total = total_.load();
  m += " after " + std::to_string(done_.load()) +
       (total ? " of " + std::to_string(total) : std::string()) + " " + what_ + "; nothing written";
  return m;
}

void CliJob::progress(std::size_t done, std::size_t total, const std::string& note) {
  done_.store(done);
  total_.store(total);
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const long long ms = std::chrono::duration_cast<std::chrono::milliseconds>(now - start_).count();
  const int decile = total ? static_cast<int>(10 * done / total) : -1;
  // A terminal: at most five redraws a second. A log: a line at each new tenth (or every 5 s
  // when the total is unknown).
  if (tty_ ? ms - last_ms_.load() < 200 && done != total
           : (total ? decile <= last_decile_.load() : ms - last_ms_.load() < 5000)) {
    return;
  }
  std::lock_guard lock(g_draw);
  last_ms_.store(ms);
  last_decile_.store(decile);
  char buf[160];
  if (total) {
    std::snprintf(buf, sizeof buf, "kfw-cli: %zu/%zu %s (%.0f %%), %.1f s", done, total,
                  what_.c_str(), 100.0 * static_cast<double>(done) / static_cast<double>(total),
                  static_cast<double>(ms) / 1000.0);
  } else {
    std::snprintf(buf, sizeof buf, "kfw-cli: %zu %s, %.1f s", done, what_.c_str(),
                  static_cast<double>(ms) / 1000.0);
  }
  err_ << (tty_ ? "\r" : "") << buf << (note.empty() ? "" : ", " + note) << (tty_ ? "" : "\n");
  err_.flush();
  drew_ = true;
}

void CliJob::finish() {
  std::lock_guard lock(g_draw);
  if (drew_ && tty_) err_ << "\n";
  drew_ = false;
}

}  // namespace kfw
