// Hardening round 2 (issue 29): long kfw-cli jobs report progress on stderr (--progress when it is
// not a terminal: a line every 10 %) and stop cleanly on SIGINT and SIGTERM as
// ../shared/STAGE.md says: no --out written, exit 130 or 143, one line saying how far it got.
// Before, `run --seeds 1..100000` printed nothing for minutes and a signal killed it mid-way.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "common/cli_runner.h"
#include "common/short_temp_dir.h"

namespace kfw {
namespace {

namespace fs = std::filesystem;

class LongJobs : public testing::ShortTempDir {
 protected:
  std::string stderr_text() const {
    std::ifstream in(dir_ + "/err.txt");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  // Starts `kfw-cli ARGS` (stderr to err.txt), waits for its first progress line, sends `sig`;
  // the exit status.
  int interrupt(const std::vector<std::string>& args, int sig) const {
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int e = ::open((dir_ + "/err.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, 1);
      ::dup2(e, 2);
      std::vector<char*> argv{const_cast<char*>(KFW_CLI)};
      for (const auto& a : args)
        argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv(KFW_CLI, argv.data());
      ::_exit(127);
    }
    for (int i = 0; i < 600 && stderr_text().find(" seeds (") == std::string::npos; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::vector<std::string> seeds_run() const {
    return {"run",
            std::string(KFW_SOURCE_DIR) + "/presets/underwater.json",
            "--seeds",
            "1..2000",
            "--progress",
            "--out",
            dir_ + "/part.json"};
  }
};

TEST_F(LongJobs, SigintStopsAMonteCarloRunWritingNothing) {
  EXPECT_EQ(interrupt(seeds_run(), SIGINT), 130) << stderr_text();
  EXPECT_FALSE(fs::exists(dir_ + "/part.json"));
  EXPECT_NE(stderr_text().find("kfw-cli: interrupted by SIGINT after "), std::string::npos)
      << stderr_text();
  EXPECT_NE(stderr_text().find(" of 2000 seeds; nothing written"), std::string::npos)
      << stderr_text();
}

TEST_F(LongJobs, SigtermExits143) {
  EXPECT_EQ(interrupt(seeds_run(), SIGTERM), 143) << stderr_text();
  EXPECT_FALSE(fs::exists(dir_ + "/part.json"));
  EXPECT_NE(stderr_text().find("interrupted by SIGTERM"), std::string::npos) << stderr_text();
}

TEST_F(LongJobs, ProgressIsALineEveryTenthWhenForced) {
  auto r = testing::run_command(std::string(KFW_CLI) + " run " + KFW_SOURCE_DIR +
                                "/presets/models/cv1d.json --seeds 1..50 --set sim.duration=3 "
                                "--progress 2>&1 >/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_NE(r.text.find("kfw-cli: 50/50 seeds (100 %)"), std::string::npos) << r.text;
  auto quiet = testing::run_command(std::string(KFW_CLI) + " run " + KFW_SOURCE_DIR +
                                    "/presets/models/cv1d.json --seeds 1..50 --set sim.duration=3 "
                                    "2>&1 >/dev/null");
  EXPECT_EQ(quiet.text.find("seeds ("), std::string::npos) << quiet.text;  // not a terminal
}

}  // namespace
}  // namespace kfw
