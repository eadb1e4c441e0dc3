// Writes are atomic (issue 16): `kfw-cli run --out existing.csv` killed with SIGKILL — at the
// test-only pause before the rename (KFW_TEST_PAUSE_BEFORE_RENAME) and at random points of a large
// write — leaves existing.csv either the old or the new complete file, 20 times out of 20.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <thread>

#include "data/output.h"

extern char** environ;

namespace kfw {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

class KillDuringWrite : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::path(::testing::TempDir()) / "kfw_kill_during_write";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // 30 000 rows at 50 Hz: an estimates file of a few MB, written in a fraction of a second.
    data = (dir / "in.csv").string();
    std::ofstream os(data);
    os << "t,gyro,angle,truth\n";
    for (int k = 0; k < 30000; ++k)
      os << 0.02 * k << ",1," << 0.02 * k << ',' << 0.02 * k << '\n';
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir);
  }

  // Starts kfw-cli run ... --out existing.csv with `pause_ms` before the rename (0: none).
  pid_t start(int pause_ms) const {
    const std::string preset = std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json";
    const std::string out = (dir / "existing.csv").string();
    std::vector<std::string> args = {KFW_CLI, "run", preset, "--data", data, "--out", out};
    std::vector<char*> argv;
    for (auto& a : args)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<std::string> env_s;
    for (char** e = environ; *e; ++e) {
      if (std::string(*e).rfind(std::string(kPauseBeforeRenameEnv) + "=", 0) != 0)
        env_s.emplace_back(*e);
    }
    if (pause_ms > 0)
      env_s.push_back(std::string(kPauseBeforeRenameEnv) + "=" + std::to_string(pause_ms));
    std::vector<char*> envp;
    for (auto& e : env_s)
      envp.push_back(e.data());
    envp.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&fa);
    EXPECT_EQ(rc, 0);
    return pid;
  }
  static int wait_exit(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
  }
  // The writer's temporaries beside existing.csv.
  std::vector<fs::path> temporaries() const {
    std::vector<fs::path> t;
    for (const auto& e : fs::directory_iterator(dir)) {
      if (e.path().filename().string().rfind(".existing.csv.kfw-", 0) == 0) t.push_back(e.path());
    }
    return t;
  }
  void reset_old() const {
    for (const auto& t : temporaries())
      fs::remove(t);
    std::ofstream(dir / "existing.csv", std::ios::binary) << kOld;
  }

  static constexpr const char* kOld = "t,theta\n0,1\n";
  fs::path dir;
  std::string data;
};

TEST_F(KillDuringWrite, ExistingFileIsAlwaysOldOrNewComplete) {
  // The new file, from an uninterrupted run, and how long such a run takes.
  reset_old();
  const auto t0 = Clock::now();
  ASSERT_EQ(wait_exit(start(0)), 0);
  const auto run_time = Clock::now() - t0;
  const std::string fresh = read(dir / "existing.csv");
  ASSERT_GT(fresh.size(), 1000000u);
  ASSERT_NE(fresh, kOld);

  // 10 kills at the pause: the temporary is complete, the rename has not happened.
  for (int i = 0; i < 10; ++i) {
    reset_old();
    const pid_t pid = start(1500);
    const auto deadline = Clock::now() + std::chrono::seconds(20);
    bool paused = false;
    while (Clock::now() < deadline && !paused) {
      for (const auto& t : temporaries()) {
        std::error_code ec;
        if (fs::file_size(t, ec) == fresh.size()) paused = true;
      }
      if (!paused) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ::kill(pid, SIGKILL);
    const int status = wait_exit(pid);
    EXPECT_TRUE(paused) << "kill " << i << ": the pause was never reached";
    EXPECT_TRUE(WIFSIGNALED(status)) << "kill " << i;
    EXPECT_EQ(read(dir / "existing.csv"), kOld) << "kill " << i << " at the pause";
  }

  // 10 kills at random points: 5 anywhere in the run (start, compute, write, rename), 5 within
  // 400 ms of the temporary's creation (the large write, the fsync, the rename).
  std::mt19937 rng(16);
  const auto span_us = std::chrono::duration_cast<std::chrono::microseconds>(run_time).count();
  std::uniform_int_distribution<long long> anywhere(0, std::max<long long>(span_us * 5 / 4, 1000));
  std::uniform_int_distribution<long long> in_write(0, 400000);
  int old_seen = 0, new_seen = 0;
  for (int i = 0; i < 10; ++i) {
    reset_old();
    const pid_t pid = start(0);
    bool reaped = false;
    if (i < 5) {
      std::this_thread::sleep_for(std::chrono::microseconds(anywhere(rng)));
    } else {
      const auto deadline = Clock::now() + std::chrono::seconds(20);
      while (temporaries().empty() && Clock::now() < deadline) {
        int st = 0;
        if (::waitpid(pid, &st, WNOHANG) == pid) {  // done before we saw it
          reaped = true;
          break;
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      std::this_thread::sleep_for(std::chrono::microseconds(in_write(rng)));
    }
    if (!reaped) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
    const std::string now = read(dir / "existing.csv");
    EXPECT_TRUE(now == kOld || now == fresh)
        << "kill " << i << ": existing.csv is neither the old nor the new file (" << now.size()
        << " bytes)";
    old_seen += now == kOld;
    new_seen += now == fresh;
  }
  std::cout << "random kills: " << old_seen << " old, " << new_seen << " new (run "
            << span_us / 1000 << " ms)\n";
  // A killed run's temporary is hidden and never read as output: existing.csv names stay intact.
  for (const auto& t : temporaries())
    EXPECT_EQ(t.filename().string().front(), '.');
}

}  // namespace
}  // namespace kfw
