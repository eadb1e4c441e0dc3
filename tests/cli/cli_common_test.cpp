// What every kfw-cli command shares: its declaration (help, --version, "did you mean"), the value
// grammar, exit codes and the one writer for output files (nothing written after an exit 2).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include "common/cli_runner.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/dataset.h"
#include "data/csv.h"

namespace {

namespace fs = std::filesystem;

using Out = kfw::testing::CliOutput;
using kfw::testing::cli;

bool has(const std::string& text, const std::string& fragment) {
  return text.find(fragment) != std::string::npos;
}

long lines(const std::string& text) {
  return std::count(text.begin(), text.end(), '\n');
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void put(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// A CSV table by column (a sweep's grid columns repeat, so read_csv's time check does not fit);
// an empty cell is NaN.
std::map<std::string, std::vector<double>> table(const fs::path& p) {
  std::map<std::string, std::vector<double>> t;
  std::ifstream in(p);
  std::string line;
  std::vector<std::string> names;
  auto fields = [](const std::string& l) {
    std::vector<std::string> f;
    std::stringstream ss(l);
    for (std::string cell; std::getline(ss, cell, ',');)
      f.push_back(cell);
    if (!l.empty() && l.back() == ',') f.emplace_back();
    return f;
  };
  if (std::getline(in, line)) names = fields(line);
  while (std::getline(in, line)) {
    const auto f = fields(line);
    for (std::size_t i = 0; i < names.size(); ++i)
      t[names[i]].push_back(i < f.size() && !f[i].empty() ? std::stod(f[i]) : std::nan(""));
  }
  return t;
}

// A short helicopter simulation keeps the runs quick.
const std::string kHeli = "helicopter --set sim.duration=10";

class CliCommon : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("kfw_cli_common_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

// Exit 2 with one line naming `fragment`.
void expect_invalid(const std::string& args, const std::string& fragment) {
  const Out o = cli(args);
  EXPECT_EQ(o.code, 2) << args << " → " << o.text;
  EXPECT_TRUE(has(o.text, fragment)) << args << " → " << o.text;
  EXPECT_EQ(lines(o.text), 1) << args << " → " << o.text;
  EXPECT_EQ(o.text.rfind("kfw-cli: ", 0), 0u) << o.text;
}

std::vector<std::string> commands() {
  std::vector<std::string> c = {"simulate", "run",    "gain", "tune", "sweep",
                                "params",   "preset", "list", "help"};
  const std::string list = cli("list").text;
  if (has(list, "underwater")) c.push_back("stats");
  if (has(list, "helicopter")) c.push_back("noise");
  return c;
}

TEST_F(CliCommon, EveryCommandHasHelp) {
  for (const auto& cmd : commands()) {
    const Out h = cli(cmd + " --help", "2>/dev/null");
    EXPECT_EQ(h.code, 0) << cmd << " → " << h.text;
    EXPECT_TRUE(has(h.text, "kfw-cli " + cmd)) << cmd << " → " << h.text;
    EXPECT_TRUE(has(h.text, "--help")) << h.text;
    const Out via_help = cli("help " + cmd, "2>/dev/null");
    EXPECT_EQ(via_help.code, 0) << cmd;
    EXPECT_EQ(via_help.text, h.text) << cmd;
  }
  EXPECT_TRUE(has(cli("run --help").text, "--metrics"));
  EXPECT_TRUE(has(cli("sweep --help").text, "--param"));
}

TEST_F(CliCommon, TopLevelHelpListsCommandsGrammarAndExitCodes) {
  const Out h = cli("--help", "2>/dev/null");
  ASSERT_EQ(h.code, 0);
  for (const auto& cmd : commands())
    EXPECT_TRUE(has(h.text, cmd)) << cmd;
  for (const char* s : {"lo:hi:n", "1..50", "i/N", "Exit codes"})
    EXPECT_TRUE(has(h.text, s)) << s;
  EXPECT_EQ(cli("help", "2>/dev/null").text, h.text);
  const Out none = cli("");
  EXPECT_EQ(none.code, 2);
  EXPECT_TRUE(has(none.text, "simulate"));
  const Out g = cli("help grammar", "2>/dev/null");
  EXPECT_EQ(g.code, 0);
  for (const char* s : {"lo:hi:n", ":log", "1..50", "3,7,9", "i/N", "index mod N = i - 1"})
    EXPECT_TRUE(has(g.text, s)) << s;
}

TEST_F(CliCommon, VersionComesFromCMake) {
  const Out v = cli("--version");
  EXPECT_EQ(v.code, 0);
  EXPECT_EQ(v.text, std::string("kfw-cli ") + KFW_VERSION + "\n");
}

TEST_F(CliCommon, MisspeltNamesGetTheNearestValidName) {
  expect_invalid("simulte helicopter", "unknown command 'simulte' (did you mean 'simulate'?)");
  expect_invalid("frobnicate", "unknown command 'frobnicate'");
  expect_invalid("help rnu", "did you mean 'run'?");
  expect_invalid("--verison", "unknown option '--verison' (did you mean '--version'?)");
  expect_invalid("run " + kHeli + " --dat x.csv",
                 "unknown option '--dat' (did you mean '--data'?)");
  // A misspelt required option is named as misspelt, not as missing.
  expect_invalid("simulate helicopter --ot x.csv", "did you mean '--out'?");
  expect_invalid("sweep " + kHeli + " --param Q=1:2:2 --metrc rmse", "did you mean '--metric'?");
  expect_invalid("run " + kHeli + " --set gama=0.1",
                 "unknown parameter 'gama' (did you mean 'gamma'?)");
  expect_invalid("params helicopter --set q=1", "did you mean 'Q'?");
  expect_invalid("tune " + kHeli + " --params Q,Rr", "--params: unknown parameter 'Rr'");
  expect_invalid("tune " + kHeli + " --params Q,Rr", "did you mean 'R'?");
  expect_invalid("sweep " + kHeli + " --param Qq=1:2:2 --metric rmse", "did you mean 'Q'?");
  expect_invalid("sweep " + kHeli + " --param Q=1:2:2 --metric rmes",
                 "--metric: unknown metric 'rmes' (did you mean 'rmse'?)");
  expect_invalid("tune " + kHeli + " --params Q --objective nsi",
                 "--objective: unknown objective 'nsi' (did you mean 'nis'?)");
  expect_invalid("run helicoptr", "did you mean 'helicopter'?");
}

TEST_F(CliCommon, MissingAndMalformedArgumentsExit2) {
  expect_invalid("simulate helicopter", "--out is required");
  expect_invalid("run", "PRESET is required");
  expect_invalid("simulate helicopter --seed abc --out x.csv", "--seed");
  expect_invalid("run " + kHeli + " extra", "unexpected argument 'extra'");
  expect_invalid("run " + kHeli + " --data /no/such.csv", "/no/such.csv");
  expect_invalid("run /no/preset.json", "cannot open preset");
}

TEST_F(CliCommon, GridGrammarOnSweep) {
  const std::string base = "sweep " + kHeli + " --metric rmse ";
  auto lg = cli(base + "--param Q=1:100:3:log", "2>/dev/null");
  ASSERT_EQ(lg.code, 0) << lg.text;
  auto j = nlohmann::json::parse(lg.text);
  EXPECT_EQ(j["points"].get<int>(), 3);
  auto lin =
      cli(base + "--param Q=1:100:3:lin --param R=1:2:2 --out " + path("s.csv"), "2>/dev/null");
  ASSERT_EQ(lin.code, 0) << lin.text;
  auto t = table(path("s.csv"));
  ASSERT_EQ(t["Q"].size(), 6u);
  EXPECT_EQ(t["Q"][2], 50.5);  // linear: 1, 1, 50.5, 50.5, 100, 100 (first axis slowest)
  const std::string p = "sweep " + kHeli + " --metric rmse --param ";
  expect_invalid(p + "Q=1:2", "--param Q: '1:2' is not a grid lo:hi:n[:log]");
  expect_invalid(p + "Q=1:2:0", "--param Q: ");
  expect_invalid(p + "Q=1:2:2.5", "whole number");
  expect_invalid(p + "Q=0:10:3:log", "lo, hi > 0");
  expect_invalid(p + "Q=1:10:3:logg", "did you mean 'log'?");
  expect_invalid(p + "Q", "--param expects key=lo:hi:n");
}

TEST_F(CliCommon, HugeTokensAreNeverEchoed) {
  const std::string huge(100'000, 'k');
  for (const std::string& args :
       {huge, "run " + kHeli + " --set " + huge + "=1", "run " + kHeli + " --set Q=" + huge,
        "run " + kHeli + " --data /" + huge, "run " + kHeli + " --" + huge,
        "sweep " + kHeli + " --metric rmse --param Q=1:2:" + huge}) {
    const Out o = cli(args);
    EXPECT_EQ(o.code, 2) << o.text.substr(0, 300);
    EXPECT_LT(o.text.size(), 400u) << o.text.substr(0, 300);
    EXPECT_EQ(lines(o.text), 1) << o.text.substr(0, 300);
  }
}

TEST_F(CliCommon, MetricsJsonHasNoNulls) {
  const Out r = cli("run " + kHeli, "2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  const auto j = nlohmann::json::parse(r.text);
  for (const auto& [k, v] : j.items())
    EXPECT_FALSE(v.is_null()) << k;
  // No truth after the columns are cut: rmse is undefined, with the reason.
  ASSERT_EQ(cli("simulate " + kHeli + " --out " + path("d.csv")).code, 0);
  ASSERT_EQ(std::system(("cut -d, -f1-3 " + path("d.csv") + " > " + path("nt.csv")).c_str()), 0);
  const Out nt = cli("run " + kHeli + " --data " + path("nt.csv"), "2>/dev/null");
  ASSERT_EQ(nt.code, 0) << nt.text;
  const auto k = nlohmann::json::parse(nt.text);
  EXPECT_FALSE(k.contains("rmse"));
  ASSERT_TRUE(k.contains("undefined")) << nt.text;
  EXPECT_TRUE(k["undefined"].contains("rmse")) << nt.text;
  const Out g = cli("gain helicopter", "2>/dev/null");
  ASSERT_EQ(g.code, 0);
  const auto gj = nlohmann::json::parse(g.text);
  for (const auto& [key, v] : gj.items())
    EXPECT_FALSE(v.is_null()) << key;
}

TEST_F(CliCommon, SweepPicksTheBestByTheMetricsDirection) {
  // whiteness_p: higher is better; rmse: lower is better.
  for (const std::string metric : {"whiteness_p", "rmse"}) {
    const std::string csv = path(metric + ".csv");
    const Out o =
        cli("sweep " + kHeli + " --param Q=1:10000:5 --metric " + metric + " --out " + csv,
            "2>/dev/null");
    ASSERT_EQ(o.code, 0) << o.text;
    const auto j = nlohmann::json::parse(o.text);
    auto t = table(csv);
    const auto& v = t[metric];
    ASSERT_EQ(v.size(), 5u);
    const double best = metric == "rmse" ? *std::min_element(v.begin(), v.end())
                                         : *std::max_element(v.begin(), v.end());
    EXPECT_EQ(j["best"].get<double>(), best) << metric;
    EXPECT_EQ(j["direction"], metric == "rmse" ? "lower" : "higher");
  }
}

TEST_F(CliCommon, TuneOutputHasNoNulls) {
  const Out o = cli("tune " + kHeli + " --params Q,R --out " + path("t.json"), "2>/dev/null");
  ASSERT_EQ(o.code, 0) << o.text;
  const auto j = nlohmann::json::parse(o.text);
  ASSERT_TRUE(j.contains("metrics"));
  for (const auto& [k, v] : j["metrics"].items())
    EXPECT_FALSE(v.is_null()) << k;
  EXPECT_TRUE(fs::exists(path("t.json")));
}

TEST_F(CliCommon, NothingIsWrittenWhenAnOutputPathIsInvalid) {
  // The output checked last is invalid: the first is neither created nor replaced.
  const std::string est = path("est.csv");
  expect_invalid("run " + kHeli + " --out " + est + " --metrics /nonexistent/m.json",
                 "/nonexistent");
  EXPECT_FALSE(fs::exists(est));
  put(est, "precious");
  expect_invalid("run " + kHeli + " --out " + est + " --metrics /nonexistent/m.json",
                 "--metrics: /nonexistent/m.json: the directory /nonexistent does not exist");
  EXPECT_EQ(slurp(est), "precious");
  expect_invalid("run " + kHeli + " --out " + dir_.string(), "is a directory");
  expect_invalid("simulate helicopter --out " + path("missing/d.csv"), "does not exist");
  expect_invalid("run " + kHeli + " --out " + est + " --metrics " + est, "already an output");
  EXPECT_EQ(slurp(est), "precious");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(CliCommon, AnInputIsNeverOverwritten) {
  ASSERT_EQ(cli("simulate " + kHeli + " --out " + path("d.csv")).code, 0);
  const std::string data = slurp(path("d.csv"));
  expect_invalid("run " + kHeli + " --data " + path("d.csv") + " --out " + path("d.csv"),
                 "is also an input");
  expect_invalid("run " + kHeli + " --data " + path("d.csv") + " --metrics " + path("./d.csv"),
                 "is also an input");
  EXPECT_EQ(slurp(path("d.csv")), data);
  // The preset file is an input too.
  fs::copy_file(std::string(KFW_SOURCE_DIR) + "/presets/helicopter.json", path("p.json"));
  const std::string preset = slurp(path("p.json"));
  expect_invalid("preset " + path("p.json") + " --set Q=100 --out " + path("p.json"),
                 "is also an input");
  EXPECT_EQ(slurp(path("p.json")), preset);
}

TEST_F(CliCommon, OutputsGoThroughSymlinksAndLeaveAUsersTmpAlone) {
  ASSERT_EQ(cli("simulate " + kHeli + " --out " + path("real.csv")).code, 0);
  fs::create_symlink("real.csv", path("link.csv"));
  put(path("link.csv.tmp"), "mine");
  const Out o = cli("simulate helicopter --set sim.duration=5 --out " + path("link.csv"));
  ASSERT_EQ(o.code, 0) << o.text;
  EXPECT_TRUE(fs::is_symlink(path("link.csv")));
  auto d = kfw::read_csv(path("real.csv"));
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d->rows(), 251u);
  EXPECT_EQ(slurp(path("link.csv.tmp")), "mine");
}

TEST_F(CliCommon, AFifoIsRefused) {
  ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0644), 0);
  expect_invalid("simulate " + kHeli + " --out " + path("fifo"), "not a regular file");
  EXPECT_TRUE(fs::is_fifo(path("fifo")));
}

// Runs kfw-cli with the test pause before its renames; `during` runs once the temporary beside
// `target` is complete (with kfw-cli's pid). Returns the exit status (waitpid) and what kfw-cli
// printed.
std::pair<int, std::string> paused_run(const std::vector<std::string>& args, const fs::path& target,
                                       const std::function<void(pid_t, const fs::path&)>& during) {
  const fs::path log = target.parent_path() / "log.txt";
  const pid_t child = ::fork();
  if (child == 0) {
    ::setenv("KFW_TEST_PAUSE_BEFORE_RENAME", "3000", 1);
    std::FILE* f = std::freopen(log.c_str(), "w", stdout);
    ::dup2(::fileno(f), 2);
    std::vector<char*> argv = {const_cast<char*>(KFW_CLI)};
    for (const auto& a : args)
      argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(KFW_CLI, argv.data());
    ::_exit(127);
  }
  const std::string prefix = "." + target.filename().string() + ".kfw-";
  bool seen = false;
  for (int i = 0; i < 1000 && !seen; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    // Error-code overloads: a temporary may vanish between the listing and its size (seen under
    // the sanitizers, where the run is slow); it is then not the one looked for.
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(target.parent_path(), ec)) {
      std::error_code size_ec;
      const auto size = fs::file_size(e.path(), size_ec);
      if (!seen && e.path().filename().string().rfind(prefix, 0) == 0 && !size_ec && size > 0) {
        seen = true;
        during(child, e.path());
      }
    }
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(seen) << "no temporary " << prefix << "XXXXXX beside " << target;
  return {status, slurp(log)};
}

TEST_F(CliCommon, AFailedWriteExits1AndKeepsTheOldFile) {
  put(path("d.csv"), "old");
  // The temporary vanishes before the rename: the write fails after the work.
  const auto [status, text] =
      paused_run({"simulate", "helicopter", "--set", "sim.duration=2", "--out", path("d.csv")},
                 dir_ / "d.csv", [](pid_t, const fs::path& temp) { fs::remove(temp); });
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << text;
  EXPECT_EQ(lines(text), 1) << text;
  EXPECT_TRUE(has(text, "kfw-cli: ") && has(text, "d.csv")) << text;
  EXPECT_EQ(slurp(path("d.csv")), "old");
}

TEST_F(CliCommon, KilledBeforeTheRenameLeavesTheOldFile) {
  put(path("d.csv"), "old");
  fs::path temp;
  const auto [status, text] =
      paused_run({"simulate", "helicopter", "--set", "sim.duration=2", "--out", path("d.csv")},
                 dir_ / "d.csv", [&temp](pid_t pid, const fs::path& t) {
                   temp = t;
                   ::kill(pid, SIGKILL);
                 });
  EXPECT_TRUE(WIFSIGNALED(status)) << text;
  EXPECT_EQ(slurp(path("d.csv")), "old");
  EXPECT_TRUE(fs::exists(temp));  // a stray uniquely named temporary, never the target
}

TEST_F(CliCommon, ScenarioCommandShorthand) {
  const std::string csv = path("uw.csv");
  ASSERT_EQ(cli("simulate underwater --set sim.duration=20 --out " + csv).code, 0);
  const Out o = cli("stats " + csv + " --set sim.duration=20", "2>/dev/null");
  EXPECT_EQ(o.code, 0) << o.text;
  EXPECT_TRUE(nlohmann::json::accept(o.text)) << o.text;
  expect_invalid("stats helicopter",
                 "'helicopter' has no command 'stats' (offered by: underwater)");
}

}  // namespace
