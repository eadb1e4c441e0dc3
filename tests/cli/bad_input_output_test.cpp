// The bad-input matrix, output paths (issue 16): missing or read-only directories, an output that
// is an input, a directory, a FIFO or a device; a symlink is written through. Each refused case:
// exit 2 before any work, one line naming the path and option, no other output touched.
#include <sys/stat.h>
#include <unistd.h>

#include "common/bad_input.h"

namespace kfw {
namespace {

using testing::cli;

class BadOutput : public testing::BadInput {
 protected:
  std::string run() const { return "run " + preset_path("helicopter") + " --data " + data_; }
  void SetUp() override {
    BadInput::SetUp();
    data_ = log("in.csv", 200);
  }
  // `--metrics BAD` beside an existing --out: the --out file must survive.
  void refused(const std::string& bad, std::initializer_list<std::string> fragments) {
    static const std::string kOld = "old estimates\n";
    std::ofstream(out, std::ios::binary) << kOld;
    const std::string before = read(data_);
    auto r = cli(run() + " --out " + out + " --metrics " + bad);
    SCOPED_TRACE(bad);
    EXPECT_EQ(r.code, 2) << r.text;
    for (const auto& f : fragments)
      EXPECT_NE(r.text.find(f), std::string::npos) << "'" << f << "' not in: " << r.text;
    EXPECT_EQ(std::count(r.text.begin(), r.text.end(), '\n'), 1) << r.text;
    EXPECT_EQ(read(out), kOld);
    EXPECT_EQ(read(data_), before);
    EXPECT_EQ(leftovers(), "");
  }
  std::string data_;
};

TEST_F(BadOutput, MissingAndReadOnlyDirectories) {
  refused("/nonexistent/dir/m.json", {"--metrics", "/nonexistent/dir"});
  refused((dir / "no" / "m.json").string(), {"--metrics", "no"});
  file("plain", "x");
  refused((dir / "plain" / "m.json").string(), {"--metrics", "plain"});
  refused("/proc/kfw_m.json", {"--metrics", "/proc"});
  std::filesystem::create_directories(dir / "ro");
  ::chmod((dir / "ro").c_str(), 0555);
  if (::geteuid() != 0) refused((dir / "ro" / "m.json").string(), {"--metrics", "ro"});
  ::chmod((dir / "ro").c_str(), 0755);
}

TEST_F(BadOutput, AnInputADirectoryAFifoOrADevice) {
  refused(data_, {"--metrics", "in.csv"});
  refused(preset_path("helicopter"), {"--metrics", "helicopter.json"});
  std::filesystem::create_directories(dir / "d.json");
  refused((dir / "d.json").string(), {"--metrics", "d.json"});
  const std::string fifo = (dir / "fifo.json").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  refused(fifo, {"--metrics", "fifo.json"});
  refused("/dev/full", {"--metrics", "/dev/full"});
  refused("/dev/null", {"--metrics", "/dev/null"});
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/full"));
  // A symlink to the input is the input.
  std::filesystem::create_symlink(data_, dir / "link.csv");
  refused((dir / "link.csv").string(), {"--metrics", "link.csv"});
  // Two options naming one file.
  refused(out, {out});
}

TEST_F(BadOutput, ASymlinkIsWrittenThroughToItsTarget) {
  std::filesystem::create_directories(dir / "real");
  const std::string target = (dir / "real" / "m.json").string();
  std::ofstream(target) << "old";
  std::filesystem::create_symlink(target, dir / "m_link.json");
  auto r = cli(run() + " --metrics " + (dir / "m_link.json").string(), "2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "m_link.json"));
  EXPECT_EQ(read(target) + "", r.text);
  EXPECT_EQ(leftovers(), "");
}

TEST_F(BadOutput, AFailedRunWritesNothing) {
  // The work fails (exit 1): neither output is created or changed.
  data_ = log("blow.csv", 300, [](int k, int j) { return k >= 100 && j == 1 ? "1e308" : "-"; });
  expect_refused(run(), 1, {"(t = "});
}

}  // namespace
}  // namespace kfw
