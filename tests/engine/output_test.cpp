// One writer for every output file: paths checked before any work, nothing written on failure,
// unique temporaries beside the target, symlinks written through.
#include "data/output.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "core/dataset.h"
#include "data/csv.h"

namespace {

namespace fs = std::filesystem;
using kfw::OutputSet;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void put(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// Files in `dir` other than the ones named.
std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

class Output : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("kfw_output_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(Output, WritesAndReplaces) {
  const fs::path f = dir_ / "a.txt";
  put(f, "old");
  OutputSet o;
  ASSERT_TRUE(o.add(f.string(), "--out").ok());
  ASSERT_TRUE(o.stage(f.string(), "new").ok());
  ASSERT_TRUE(o.commit().ok());
  EXPECT_EQ(slurp(f), "new");
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"a.txt"});  // no temporary left
}

TEST_F(Output, KeepsTheReplacedFilesPermissions) {
  const fs::path f = dir_ / "a.txt";
  put(f, "old");
  fs::permissions(f, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  ASSERT_TRUE(kfw::write_file_atomic(f.string(), "new").ok());
  EXPECT_EQ(fs::status(f).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

TEST_F(Output, RefusesBadPathsBeforeAnyWork) {
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const fs::path sub = dir_ / "sub";
  fs::create_directory(sub);
  const fs::path file = dir_ / "file";
  put(file, "x");
  struct Case {
    std::string path, fragment;
  };
  for (const Case& c :
       {Case{sub.string(), "is a directory"}, Case{fifo.string(), "not a regular file"},
        Case{"/dev/null", "not a regular file"},
        Case{(dir_ / "missing" / "m.json").string(), "does not exist"},
        Case{(file / "m.json").string(), "is not a directory"}, Case{"", "empty"}}) {
    OutputSet o;
    auto st = o.add(c.path, "--metrics");
    ASSERT_FALSE(st.ok()) << c.path;
    EXPECT_EQ(st.err().exit_code, kfw::kExitInvalid) << c.path;
    EXPECT_EQ(st.error().rfind("--metrics: ", 0), 0u) << st.error();
    EXPECT_NE(st.error().find(c.fragment), std::string::npos) << st.error();
  }
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_TRUE(fs::is_directory(sub));
}

TEST_F(Output, RefusesAnInputOfTheCommand) {
  const fs::path in = dir_ / "data.csv";
  put(in, "t,x\n0,1\n");
  OutputSet o;
  o.add_input(in.string());
  auto st = o.add((dir_ / "." / "data.csv").string(), "--out");  // the same file, spelt otherwise
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.err().exit_code, kfw::kExitInvalid);
  EXPECT_NE(st.error().find("also an input"), std::string::npos) << st.error();
  // Through a symlink too.
  const fs::path link = dir_ / "link.csv";
  fs::create_symlink(in, link);
  EXPECT_FALSE(o.add(link.string(), "--out").ok());
  EXPECT_EQ(slurp(in), "t,x\n0,1\n");
}

TEST_F(Output, RefusesTheSameOutputTwice) {
  OutputSet o;
  ASSERT_TRUE(o.add((dir_ / "m.json").string(), "--out").ok());
  auto st = o.add((dir_ / "m.json").string(), "--metrics");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("already an output"), std::string::npos) << st.error();
}

TEST_F(Output, NothingIsWrittenWhenADeclarationFails) {
  // The CLI's `run --out est.csv --metrics /nonexistent/m.json`: the second declaration fails,
  // the command stops before any work and est.csv is untouched.
  const fs::path est = dir_ / "est.csv";
  put(est, "precious");
  OutputSet o;
  ASSERT_TRUE(o.add(est.string(), "--out").ok());
  ASSERT_FALSE(o.add("/nonexistent/m.json", "--metrics").ok());
  EXPECT_EQ(slurp(est), "precious");
}

TEST_F(Output, SymlinkIsWrittenThroughToItsTarget) {
  const fs::path real_dir = dir_ / "real";
  fs::create_directory(real_dir);
  const fs::path target = real_dir / "target.txt";
  put(target, "old");
  const fs::path link = dir_ / "link.txt";
  fs::create_symlink(fs::path("real") / "target.txt", link);  // relative link
  ASSERT_TRUE(kfw::write_file_atomic(link.string(), "new").ok());
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(slurp(target), "new");
  EXPECT_EQ(listing(real_dir), std::vector<std::string>{"target.txt"});
  // A dangling link creates its target.
  const fs::path dangling = dir_ / "dangling.txt";
  fs::create_symlink(real_dir / "new.txt", dangling);
  ASSERT_TRUE(kfw::write_file_atomic(dangling.string(), "fresh").ok());
  EXPECT_TRUE(fs::is_symlink(dangling));
  EXPECT_EQ(slurp(real_dir / "new.txt"), "fresh");
  // A loop is refused.
  fs::create_symlink(dir_ / "loop_b", dir_ / "loop_a");
  fs::create_symlink(dir_ / "loop_a", dir_ / "loop_b");
  auto st = kfw::write_file_atomic((dir_ / "loop_a").string(), "x");
  ASSERT_FALSE(st.ok());
  EXPECT_NE(st.error().find("symbolic links"), std::string::npos) << st.error();
}

TEST_F(Output, AUsersOwnTmpFileIsLeftAlone) {
  // The old writer used the fixed name PATH.tmp and deleted a user's file of that name.
  const fs::path f = dir_ / "out.csv";
  put(dir_ / "out.csv.tmp", "mine");
  ASSERT_TRUE(kfw::write_file_atomic(f.string(), "data").ok());
  EXPECT_EQ(slurp(dir_ / "out.csv.tmp"), "mine");
  EXPECT_EQ(slurp(f), "data");
  // The GUI's writer (presets, sessions) goes through the same code.
  ASSERT_TRUE(kfw::write_text_file_atomic(f.string(), "again").ok());
  EXPECT_EQ(slurp(dir_ / "out.csv.tmp"), "mine");
  EXPECT_EQ(slurp(f), "again");
  EXPECT_EQ(listing(dir_), (std::vector<std::string>{"out.csv", "out.csv.tmp"}));
}

TEST_F(Output, AFailedCommitRemovesItsTemporariesAndKeepsTheOldFiles) {
  const fs::path a = dir_ / "a.txt";
  put(a, "old a");
  const fs::path sub = dir_ / "sub";
  fs::create_directory(sub);
  OutputSet o;
  ASSERT_TRUE(o.add(a.string(), "--out").ok());
  ASSERT_TRUE(o.add((sub / "b.txt").string(), "--metrics").ok());
  ASSERT_TRUE(o.stage(a.string(), "new a").ok());
  ASSERT_TRUE(o.stage((sub / "b.txt").string(), "new b").ok());
  fs::remove_all(sub);  // the second temporary cannot be created
  auto st = o.commit();
  ASSERT_FALSE(st.ok());
  EXPECT_EQ(st.err().exit_code, kfw::kExitFailed);
  EXPECT_EQ(slurp(a), "old a");
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"a.txt"});  // a's temporary removed
}

TEST_F(Output, StagingAnUndeclaredPathIsAFailure) {
  OutputSet o;
  EXPECT_FALSE(o.stage((dir_ / "x").string(), "x").ok());
}

TEST_F(Output, UnstagedOutputsAreNotWritten) {
  OutputSet o;
  ASSERT_TRUE(o.add((dir_ / "x").string()).ok());
  ASSERT_TRUE(o.commit().ok());
  EXPECT_FALSE(fs::exists(dir_ / "x"));
}

TEST_F(Output, KilledBeforeTheRenameLeavesTheTargetIntact) {
  // KFW_TEST_PAUSE_BEFORE_RENAME holds the writer after its temporary is complete; a SIGKILL
  // there leaves the old file as it was and a uniquely named temporary beside it.
  const fs::path f = dir_ / "est.csv";
  put(f, "old");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::setenv(kfw::kPauseBeforeRenameEnv, "20000", 1);
    auto st = kfw::write_file_atomic(f.string(), "new");
    ::_exit(st.ok() ? 0 : 3);
  }
  bool temp_seen = false;
  std::string temp_name;
  for (int i = 0; i < 500 && !temp_seen; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    for (const auto& n : listing(dir_)) {
      if (n.rfind(".est.csv.kfw-", 0) == 0 && slurp(dir_ / n) == "new") {
        temp_seen = true;
        temp_name = n;
      }
    }
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(temp_seen);
  EXPECT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(slurp(f), "old");
  EXPECT_EQ(temp_name.size(), std::string(".est.csv.kfw-XXXXXX").size());
}

TEST_F(Output, NewFilesFollowTheUmask) {
  const mode_t old = ::umask(027);
  const auto st = kfw::write_file_atomic((dir_ / "n.txt").string(), "x");
  ::umask(old);
  ASSERT_TRUE(st.ok()) << st.error();
  EXPECT_EQ(fs::status(dir_ / "n.txt").permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

TEST_F(Output, HugePathsAreNotEchoed) {
  const std::string huge = "/nonexistent/" + std::string(100'000, 'p');
  OutputSet o;
  auto st = o.add(huge, "--out");
  ASSERT_FALSE(st.ok());
  EXPECT_LT(st.error().size(), 400u);
}

}  // namespace
