// Hardening round 2 (issue 29): a temporary left by a killed write (".NAME.kfw-XXXXXX", 100 MB in
// the report) is removed by the next write to the same target. A live writer holds flock on its
// temporary until the rename, so the next writer removes only temporaries whose lock it can take
// and that are at least a second old; a locked or brand-new one is left alone.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "common/cli_runner.h"
#include "common/short_temp_dir.h"
#include "data/output.h"

namespace kfw {
namespace {

namespace fs = std::filesystem;

class StaleTemporaries : public testing::ShortTempDir {
 protected:
  void SetUp() override {
    ShortTempDir::SetUp();
    out_ = dir_ + "/est.csv";
  }
  // A temporary as a writer leaves it; `age_s` seconds old (negative: in the future).
  std::string temporary(const std::string& suffix, int age_s) const {
    const std::string p = dir_ + "/.est.csv.kfw-" + suffix;
    std::ofstream(p) << std::string(1000, 'x');
    const auto when = std::chrono::system_clock::now() - std::chrono::seconds(age_s);
    const auto s = std::chrono::duration_cast<std::chrono::seconds>(when.time_since_epoch());
    struct timeval tv[2] = {{static_cast<time_t>(s.count()), 0},
                            {static_cast<time_t>(s.count()), 0}};
    EXPECT_EQ(::utimes(p.c_str(), tv), 0);
    return p;
  }
  testing::CliOutput write_out(const std::string& env = "") const {
    return testing::run_command(env + std::string(KFW_CLI) + " run " + KFW_SOURCE_DIR +
                                "/presets/helicopter.json --set sim.duration=2 --out " + out_ +
                                " 2>&1");
  }
  std::string out_;
};

TEST_F(StaleTemporaries, TheNextWriteRemovesOnlyDeadWritersTemporaries) {
  const std::string dead = temporary("Dead01", 60);
  // Younger than a second whenever the writer looks (a slow sanitizer build starts in > 1 s):
  // stamped a minute ahead.
  const std::string fresh = temporary("Fresh1", -60);
  const std::string live = temporary("Live01", 60);
  const int fd = ::open(live.c_str(), O_RDONLY);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // a writer still at work
  auto r = write_out();
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_TRUE(fs::exists(fresh));
  EXPECT_TRUE(fs::exists(live));
  ::close(fd);
  EXPECT_TRUE(fs::exists(out_));
}

TEST_F(StaleTemporaries, AWriterKilledBeforeItsRenameLeavesNothingAfterTheNextWrite) {
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::setenv(kPauseBeforeRenameEnv, "20000", 1);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    const std::string preset = std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json";
    ::execl(KFW_CLI, KFW_CLI, "run", preset.c_str(), "--set", "sim.duration=2", "--out",
            out_.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Wait for its temporary, then kill it before the rename.
  bool seen = false;
  for (int i = 0; i < 200 && !seen; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    for (const auto& e : fs::directory_iterator(dir_))
      seen = seen || e.path().filename().string().rfind(".est.csv.kfw-", 0) == 0;
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  ASSERT_TRUE(seen) << "the writer never made its temporary";
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));  // older than a live one can be
  auto r = write_out();
  ASSERT_EQ(r.code, 0) << r.text;
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().rfind(".est.csv.kfw-", 0), std::string::npos)
        << e.path();
}

}  // namespace
}  // namespace kfw
