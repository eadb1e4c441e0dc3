// Hardening round 2 (issue 29): one input policy for every file kfw-cli reads. A FIFO, a device
// (/dev/zero, /dev/urandom) or a directory given as data, preset, model file, mapping, session or
// merge part is refused at once with exit 2, naming the file and the kind — before, a FIFO blocked
// forever and a device was read until memory ran out (std::bad_alloc, SIGABRT).
#include <stdlib.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>

#include "common/bad_input.h"

namespace kfw {
namespace {

using testing::cli;

class InputPolicy : public testing::BadInput {
 protected:
  // A short folder: messages shorten paths past 80 characters.
  void SetUp() override {
    BadInput::SetUp();
    char tmpl[] = "/tmp/kfwipXXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    short_ = tmpl;
  }
  void TearDown() override {
    std::filesystem::remove_all(short_);
    BadInput::TearDown();
  }
  std::string fifo() {
    const std::string p = short_ + "/pipe.csv";
    EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0);
    return p;
  }
  std::string dir() {
    const std::string p = short_ + "/folder.csv";
    std::filesystem::create_directory(p);
    return p;
  }
  std::string short_;
  // Refused with exit 2 within a few seconds, naming the path and `what`.
  void refused_fast(const std::string& args, const std::string& path,
                    std::initializer_list<std::string> what) {
    const auto t0 = std::chrono::steady_clock::now();
    auto r = testing::run_command("timeout 20 " + std::string(KFW_CLI) + " " + args + " 2>&1");
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.code, 2) << args << "\n" << r.text;
    EXPECT_LT(s, 10.0) << args;
    EXPECT_NE(r.text.find(path), std::string::npos) << r.text;
    for (const auto& w : what)
      EXPECT_NE(r.text.find(w), std::string::npos) << "'" << w << "' not in: " << r.text;
  }
};

TEST_F(InputPolicy, DataFromAFifoADeviceOrADirectoryIsRefusedAtOnce) {
  const std::string heli = preset_path("helicopter");
  const std::string p = fifo(), d = dir();
  refused_fast("run " + heli + " --data " + p, p, {"not a regular file (a FIFO)", "data file"});
  refused_fast("run " + heli + " --data /dev/urandom", "/dev/urandom",
               {"not a regular file (a character device)"});
  refused_fast("run " + heli + " --data " + d, d, {"is a directory"});
  refused_fast("inspect /dev/urandom", "/dev/urandom", {"not a regular file"});
  refused_fast("inspect " + p, p, {"not a regular file (a FIFO)"});
}

TEST_F(InputPolicy, JsonInputsFromAFifoADeviceOrADirectoryAreRefusedAtOnce) {
  const std::string heli = preset_path("helicopter");
  const std::string p = fifo(), d = dir();
  for (const std::string& bad : {p, std::string("/dev/zero"), d}) {
    SCOPED_TRACE(bad);
    const char* why = bad == d ? "is a directory" : "not a regular file";
    refused_fast("run " + bad, bad, {why, "preset"});
    refused_fast("run " + heli + " --data " + std::string(KFW_SOURCE_DIR) +
                     "/data/helicopter.csv --mapping " + bad,
                 bad, {why, "mapping"});
    refused_fast("merge " + bad + " " + bad, bad, {why, "part"});
    refused_fast("upgrade " + bad + " --check", bad, {why});
  }
}

TEST_F(InputPolicy, TheLimitsTableDocumentsEveryInputKind) {
  const std::string doc = source("docs/limits.md");
  for (const char* kind : {"data file", "preset", "model file", "mapping", "session", "part"})
    EXPECT_NE(doc.find(std::string("| ") + kind), std::string::npos) << kind;
}

}  // namespace
}  // namespace kfw
