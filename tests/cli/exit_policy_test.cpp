// The exit-code and missing/invalid-data rules (README "Exit codes" and "Missing and invalid
// data"), one case at least per rule, through kfw-cli: 0 the work was done (a physical outcome is
// a result), 2 invalid input or output path (nothing written), 1 the work failed.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/cli_runner.h"

namespace kfw {
namespace {

namespace fs = std::filesystem;
using testing::cli;

class ExitPolicy : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: ctest runs the tests in parallel processes.
    dir = fs::path(::testing::TempDir()) /
          ("kfw_exit_policy_" +
           std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  std::string file(const std::string& name, const std::string& text) {
    const auto p = (dir / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
  // A helicopter log of n rows at 50 Hz; `cell(k, col)` may override a cell.
  std::string log(const std::string& name, int n,
                  const std::function<std::string(int, int)>& cell = {}) {
    std::ostringstream os;
    os << "t,gyro,angle,truth\n";
    for (int k = 0; k < n; ++k) {
      const double t = 0.02 * k;
      std::string c[4] = {std::to_string(t), "1", std::to_string(t), std::to_string(t)};
      for (int j = 0; j < 4; ++j) {
        if (cell) {
          auto o = cell(k, j);
          if (o != "-") c[j] = o;
        }
      }
      os << c[0] << ',' << c[1] << ',' << c[2] << ',' << c[3] << '\n';
    }
    return file(name, os.str());
  }
  fs::path dir;
};

struct Case {
  std::string name;
  std::string args;  // after "run PRESET" unless it starts with '!'
  int code;
  std::string fragment;
};

TEST_F(ExitPolicy, TableOfRules) {
  const std::string preset = std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json";
  const std::string good = log("good.csv", 300);
  const std::string missing = log("missing.csv", 300, [](int k, int j) {
    return (k % 3 == 0 && j == 2) ? "" : (k % 7 == 0 && j == 1 ? "NaN" : "-");
  });
  const std::string inf =
      log("inf.csv", 300, [](int k, int j) { return k == 120 && j == 1 ? "inf" : "-"; });
  const std::string overflow =
      log("overflow.csv", 300, [](int k, int j) { return k == 50 && j == 2 ? "1e999" : "-"; });
  const std::string text =
      log("text.csv", 300, [](int k, int j) { return k == 5 && j == 1 ? "abc" : "-"; });
  const std::string empty_angle =
      log("noangle.csv", 300, [](int, int j) { return j == 2 ? "" : "-"; });
  const std::string no_time =
      log("notime.csv", 300, [](int k, int j) { return k == 10 && j == 0 ? "" : "-"; });
  const std::string extra = file(
      "extra.csv", "t,gyro,angle,truth,comment\n0,1,0,0,hello\n0.02,1,0,0,inf\n0.04,1,0,0,x\n");
  const std::string blowup =
      log("blowup.csv", 300, [](int k, int j) { return k >= 100 && j == 1 ? "1e308" : "-"; });
  std::string big_preset;
  {
    std::ifstream in(preset);
    std::ostringstream os;
    os << in.rdbuf();
    big_preset = os.str();
    big_preset.replace(big_preset.find("\"value\": 67.24"), 14, "\"value\": 1e999");
  }
  const std::string overflow_preset = file("overflow_preset.json", big_preset);
  const std::string out = (dir / "out.csv").string();
  const std::string m = (dir / "m.json").string();
  const Case cases[] = {
      {"the work was done", "--data " + good, 0, "\"rmse\""},
      {"missing samples are not errors", "--data " + missing, 0, "\"nis_mean\""},
      {"columns bound to no role are not validated", "--data " + extra, 0, "\"nis_mean\""},
      {"inf is invalid", "--data " + inf, 2, "inf.csv:122:"},
      {"overflow is invalid", "--data " + overflow, 2, "overflow.csv:52:"},
      {"text is invalid", "--data " + text, 2, "text.csv:7:"},
      {"a required column with no value", "--data " + empty_angle, 2,
       "column 'angle' has no value"},
      {"time on every row", "--data " + no_time, 2, "notime.csv:12:1: column 't' is empty"},
      {"a run that breaks down stops with step and time", "--data " + blowup, 1, "(t = "},
      {"a bad argument", "--data " + good + " --set Q=abc", 2, "'abc' is not a number"},
      {"a parameter-only variance that is not positive", "--data " + good + " --set R=-1", 2, "R"},
      {"an output path in a missing directory",
       "--data " + good + " --out " + out + " --metrics /nonexistent/dir/m.json", 2,
       "/nonexistent/dir"},
      {"an output path that is the input", "--data " + good + " --out " + good, 2, "good.csv"},
      {"!an overflowing number in a preset", "run " + overflow_preset + " --out " + out, 2,
       "parameters.Q.value: number overflows a double"},
      {"!an unknown command", "rnu " + preset, 2, "run"},
  };
  for (const auto& c : cases) {
    fs::remove(out);
    fs::remove(m);
    const std::string args =
        c.name[0] == '!' ? c.args : "run " + preset + " " + c.args + (c.code == 0 ? "" : "");
    const std::string before_good = [&] {
      std::ifstream in(good);
      std::ostringstream os;
      os << in.rdbuf();
      return os.str();
    }();
    auto r = cli(args + (c.code != 0 && c.args.find("--out") == std::string::npos
                             ? " --out " + out + " --metrics " + m
                             : ""));
    EXPECT_EQ(r.code, c.code) << c.name << "\n" << r.text;
    EXPECT_NE(r.text.find(c.fragment), std::string::npos) << c.name << "\n" << r.text;
    if (c.code != 0) {
      EXPECT_FALSE(fs::exists(out)) << c.name << ": an output file after exit " << c.code;
      EXPECT_FALSE(fs::exists(m)) << c.name << ": an output file after exit " << c.code;
      EXPECT_EQ(std::count(r.text.begin(), r.text.end(), '\n'), 1) << c.name << "\n" << r.text;
      EXPECT_EQ(r.text.find("null"), std::string::npos) << c.name;
    }
    std::ifstream in(good);
    std::ostringstream now;
    now << in.rdbuf();
    EXPECT_EQ(now.str(), before_good) << c.name << ": the input was changed";
  }
}

TEST_F(ExitPolicy, ManyRunsFailOnlyWhenNoneSucceeded) {
  const std::string preset = std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json";
  const std::string blowup =
      log("blowup.csv", 300, [](int k, int j) { return k >= 100 && j == 1 ? "1e308" : "-"; });
  const std::string out = (dir / "sweep.csv").string();
  // Every run of the grid stops: the sweep failed (exit 1), and wrote nothing.
  auto r = cli("sweep " + preset + " --data " + blowup + " --param Q=1:100:3 --metric rmse --out " +
               out);
  EXPECT_EQ(r.code, 1) << r.text;
  EXPECT_NE(r.text.find("every run stopped"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("(t = "), std::string::npos) << r.text;
  EXPECT_FALSE(fs::exists(out));
  // On good data nothing stops and the list is empty.
  auto ok = cli("sweep " + preset + " --data " + log("good.csv", 300) +
                " --param Q=1:100:3 --metric rmse");
  EXPECT_EQ(ok.code, 0) << ok.text;
  EXPECT_NE(ok.text.find("\"stopped\": []"), std::string::npos) << ok.text;
}

TEST_F(ExitPolicy, AHugeGridIsRefusedAtOnce) {
  const std::string preset = std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json";
  const auto start = std::chrono::steady_clock::now();
  auto r = cli("sweep " + preset + " --param Q=1:100:100000000 --metric rmse");
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find("1000000"), std::string::npos) << r.text;
  auto both = cli("sweep " + preset + " --param Q=1:100:2000 --param R=1:100:2000 --metric rmse");
  EXPECT_EQ(both.code, 2) << both.text;
  EXPECT_NE(both.text.find("--max-points"), std::string::npos) << both.text;
  EXPECT_LT(std::chrono::steady_clock::now() - start,
            std::chrono::seconds(5) * testing::kTimeScale);
  auto raised = cli("sweep " + preset + " --param Q=1:100:3 --metric rmse --max-points 2");
  EXPECT_EQ(raised.code, 2) << raised.text;
}

TEST_F(ExitPolicy, MetricsAreDeclaredOnceAndListed) {
  auto r = cli("metrics helicopter --markdown");
  EXPECT_EQ(r.code, 0) << r.text;
  for (const char* key : {"`rmse`", "`nis_mean`", "`whiteness_p.<channel>`", "`derived.k1`"})
    EXPECT_NE(r.text.find(key), std::string::npos) << key;
  auto bad = cli("metrics helicoptr");
  EXPECT_EQ(bad.code, 2);
}

TEST_F(ExitPolicy, APhysicalOutcomeIsAResult) {
  // Ball-and-beam without the detection circuit: the ball may leave the beam; either way the run
  // is a result (exit 0) and left_beam_at_s is a metric or listed as undefined with a reason.
  const std::string preset = std::string(KFW_SOURCE_DIR) + "/presets/ballbeam.json";
  auto r = cli("run " + preset + " --set detection=0");
  EXPECT_EQ(r.code, 0) << r.text;
  EXPECT_NE(r.text.find("left_beam_at_s"), std::string::npos) << r.text;
  EXPECT_EQ(r.text.find("null"), std::string::npos) << r.text;
}

}  // namespace
}  // namespace kfw
