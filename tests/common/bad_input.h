// The bad-input matrix (issue 16): one fixture for every loader's CLI test. Each case runs
// kfw-cli with outputs that already exist (known content) or do not, and asserts the exit code, a
// one-line message naming the file and line/column/key, and that no output was created, truncated
// or half-written and no temporary file (".NAME.kfw-XXXXXX") was left behind.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <sstream>
#include <string>

#include "common/cli_runner.h"

namespace kfw::testing {

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: ctest runs the tests in parallel processes.
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir = std::filesystem::path(::testing::TempDir()) /
          ("kfw_bad_" + std::string(info->test_suite_name()) + "_" + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    out = (dir / "out.csv").string();
    metrics = (dir / "m.json").string();
  }
  void TearDown() override {
    std::error_code ec;
    std::filesystem::permissions(dir, std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::add, ec);
    if (!HasFailure()) std::filesystem::remove_all(dir, ec);
  }

  std::string file(const std::string& name, const std::string& text) const {
    const auto p = (dir / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  static std::string read(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream os;
    os << in.rdbuf();
    return os.str();
  }
  static std::string source(const std::string& rel) {
    return read(std::string(KFW_SOURCE_DIR) + "/" + rel);
  }
  static std::string preset_path(const std::string& name) {
    return std::string(KFW_SOURCE_DIR) + "/presets/" + name + ".json";
  }
  // A helicopter log: n rows at 50 Hz, t,gyro,angle,truth; `cell(k, col)` may override a cell
  // (return "-" to keep it).
  std::string log(const std::string& name, int n,
                  const std::function<std::string(int, int)>& cell = {}) const {
    std::ostringstream os;
    os << "t,gyro,angle,truth\n";
    for (int k = 0; k < n; ++k) {
      const double t = 0.02 * k;
      std::string c[4] = {std::to_string(t), "1", std::to_string(t), std::to_string(t)};
      for (int j = 0; j < 4 && cell; ++j) {
        if (auto o = cell(k, j); o != "-") c[j] = o;
      }
      os << c[0] << ',' << c[1] << ',' << c[2] << ',' << c[3] << '\n';
    }
    return file(name, os.str());
  }

  // Runs `kfw-cli ARGS --out OUT --metrics M` (the output options are appended when `outputs`),
  // with OUT existing (known content) and M absent, and checks the whole contract of a refused
  // or failed command. Returns the output for further checks.
  CliOutput expect_refused(const std::string& args, int code,
                           std::initializer_list<std::string> fragments, bool outputs = true) {
    static const std::string kOld = "old content, must survive\n";
    std::ofstream(out, std::ios::binary) << kOld;
    std::filesystem::remove(metrics);
    const std::string cmd = args + (outputs ? " --out " + out + " --metrics " + metrics : "");
    CliOutput r = cli(cmd);
    SCOPED_TRACE(cmd);
    EXPECT_EQ(r.code, code) << r.text;
    for (const auto& f : fragments)
      EXPECT_NE(r.text.find(f), std::string::npos) << "'" << f << "' not in: " << r.text;
    EXPECT_EQ(std::count(r.text.begin(), r.text.end(), '\n'), 1) << "not one line: " << r.text;
    EXPECT_LT(r.text.size(), 600u) << "a long message: " << r.text.substr(0, 600);
    EXPECT_EQ(r.text.rfind("kfw-cli: ", 0), 0u) << r.text;
    EXPECT_EQ(r.text.find("null"), std::string::npos) << r.text;
    if (outputs) {
      EXPECT_EQ(read(out), kOld) << "an existing output was changed";
      EXPECT_FALSE(std::filesystem::exists(metrics)) << "an output was created";
    }
    EXPECT_EQ(leftovers(), "") << "temporary files left";
    return r;
  }

  // Temporary files of the output writer left anywhere under the test's folder.
  std::string leftovers() const {
    std::string found;
    std::error_code ec;
    for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
         it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
      if (ec) break;
      const auto name = it->path().filename().string();
      if (name.find(".kfw-") != std::string::npos || name.ends_with(".tmp")) found += name + " ";
    }
    return found;
  }

  std::filesystem::path dir;
  std::string out;
  std::string metrics;
};

}  // namespace kfw::testing
