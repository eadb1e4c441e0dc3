// The cluster path (issue 33, docs/cluster.md): scripts/slurm_submit.sh runs a sweep, a Monte
// Carlo run or a tuning as a Slurm array of scripts/slurm/kfw_task.sh, then one merge; `kfw-cli
// merge --resume DIR` lists the missing or invalid parts and the wrapper resubmits exactly those.
// On every run the job-script contract is checked against a fake sbatch (tests/common/fake_slurm:
// each array index run at once with SLURM_ARRAY_TASK_ID); the real single-node Slurm test starts
// munged, slurmctld and slurmd (scripts/slurm/single_node.sh) and skips, quoting the failing
// line, where they cannot start. Outputs are byte-identical to the local run, and for every --jobs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "common/cli_runner.h"
#include "common/short_temp_dir.h"

namespace kfw {
namespace scale_slurm_cli_test {
namespace {

namespace fs = std::filesystem;
using testing::cli;
using testing::run_command;

const std::string kSource = KFW_SOURCE_DIR;
const std::string kCv1d = kSource + "/presets/models/cv1d.json";
const std::string kSweep = " --param sigma_a=0.01:10:12 --param sigma_r=0.1:10:5 --metric rmse";

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

struct Folder {
  fs::path path;
  Folder() {
    path = fs::temp_directory_path() /
           ("kfw_slurm_" + std::to_string(::getpid()) + "_" + std::to_string(counter()++));
    fs::create_directories(path);
  }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  static int& counter() {
    static int n = 0;
    return n;
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

// The wrapper with the fake sbatch first on PATH; `fail` lists array indices that fail.
testing::CliOutput submit(const Folder& f, const std::string& args, const std::string& fail = "") {
  const std::string env = "PATH=" + kSource +
                          "/tests/common/fake_slurm:$PATH KFW_CLI=" + std::string(KFW_CLI) +
                          " FAKE_SBATCH_STATE=" + (f / "sbatch") +
                          " FAKE_SBATCH_LOG=" + (f / "sbatch.log") + " FAKE_SBATCH_FAIL=" + fail;
  return run_command(env + " bash " + kSource + "/scripts/slurm_submit.sh " + args + " 2>&1");
}

// A sweep over 4 tasks where task 3 fails: no merged result; merge --resume names 3; the
// resubmission runs index 3 alone and the merged sweep equals the local one byte for byte.
TEST(ScaleSlurm, FakeSbatchSweepResumesExactlyTheFailedTask) {
  Folder f;
  const std::string out = f / "out";
  auto o = submit(f, out + " 4 sweep " + kCv1d + kSweep, "3");
  ASSERT_EQ(o.code, 0) << o.text;
  EXPECT_FALSE(fs::exists(out + "/sweep.json"));
  EXPECT_TRUE(fs::exists(out + "/part_1.json") && fs::exists(out + "/part_4.json"));
  EXPECT_FALSE(fs::exists(out + "/part_3.json"));
  auto r = cli("merge --resume " + out, "2>/dev/null");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.text, "3\n");
  o = submit(f, "--resume " + out);
  ASSERT_EQ(o.code, 0) << o.text;
  EXPECT_NE(o.text.find("array"), std::string::npos) << o.text;
  const std::string log = slurp(f / "sbatch.log");
  EXPECT_NE(log.find("array=1-4"), std::string::npos) << log;
  EXPECT_NE(log.find("array=3\n"), std::string::npos) << log;
  EXPECT_NE(log.find("cancelled"), std::string::npos) << log;  // the first merge
  ASSERT_EQ(cli("sweep " + kCv1d + kSweep + " --out " + (f / "local.json")).code, 0);
  EXPECT_EQ(slurp(out + "/sweep.json"), slurp(f / "local.json"));
  EXPECT_EQ(cli("merge --resume " + out, "2>/dev/null").text, "\n");
  // Complete: --resume submits the merge alone.
  o = submit(f, "--resume " + out);
  EXPECT_EQ(o.code, 0) << o.text;
  EXPECT_EQ(o.text.find("array"), std::string::npos) << o.text;
}

// Every number to 1e-12 of its magnitude (at least 1), everything else equal.
::testing::AssertionResult same_to_rounding(const nlohmann::json& a, const nlohmann::json& b,
                                            const std::string& at = "") {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    if (std::abs(x - y) <= 1e-12 * std::max(1.0, std::abs(y))) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << at << ": " << x << " vs " << y;
  }
  if (a.type() != b.type() || a.size() != b.size()) {
    return ::testing::AssertionFailure() << at << ": " << a.dump() << " vs " << b.dump();
  }
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (!b.contains(it.key())) return ::testing::AssertionFailure() << at << "." << it.key();
      if (auto r = same_to_rounding(*it, b.at(it.key()), at + "." + it.key()); !r) return r;
    }
    return ::testing::AssertionSuccess();
  }
  if (a.is_array()) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (auto r = same_to_rounding(a[i], b[i], at + "[" + std::to_string(i) + "]"); !r) return r;
    }
    return ::testing::AssertionSuccess();
  }
  return a == b ? ::testing::AssertionSuccess() : ::testing::AssertionFailure() << at;
}

// Monte Carlo over 3 tasks: the merged metrics equal the local run's.
TEST(ScaleSlurm, FakeSbatchMonteCarloEqualsTheLocalRun) {
  Folder f;
  const std::string out = f / "out";
  const auto o = submit(f, out + " 3 run " + kCv1d + " --seeds 1..12");
  ASSERT_EQ(o.code, 0) << o.text;
  ASSERT_EQ(
      cli("run " + kCv1d + " --seeds 1..12 --metrics " + (f / "local.json"), "2>/dev/null").code,
      0);
  // The per-step sums add the seeds shard by shard: equal to rounding, not to the bit.
  EXPECT_TRUE(same_to_rounding(nlohmann::json::parse(slurp(out + "/metrics.json")),
                               nlohmann::json::parse(slurp(f / "local.json"))));
  EXPECT_TRUE(fs::exists(out + "/montecarlo.json"));
}

// A tuning over 3 starts: start 1 is the local tuning; the merge keeps the lowest objective.
TEST(ScaleSlurm, FakeSbatchTuneKeepsTheBestStart) {
  Folder f;
  const std::string out = f / "out";
  const std::string tune = "tune " + kCv1d + " --budget 40";
  const auto o = submit(f, out + " 3 " + tune);
  ASSERT_EQ(o.code, 0) << o.text;
  double best = INFINITY;
  std::string best_text;
  for (int i = 1; i <= 3; ++i) {
    const auto j = nlohmann::json::parse(slurp(out + "/part_" + std::to_string(i) + ".json"));
    EXPECT_EQ(j.at("kind"), "tune");
    EXPECT_EQ(j.at("shard"), std::to_string(i) + "/3");
    if (j.at("objective_value").get<double>() < best) {
      best = j.at("objective_value").get<double>();
      best_text = j.at("preset_text").get<std::string>();
    }
    if (i == 1) {
      ASSERT_EQ(cli(tune + " --out " + out + "/local.json", "2>/dev/null").code, 0);
      EXPECT_EQ(j.at("preset_text").get<std::string>(), slurp(out + "/local.json"));
    }
  }
  EXPECT_EQ(slurp(out + "/tuned.json"), best_text);
  const auto report = nlohmann::json::parse(slurp(out + "/tune.json"));
  EXPECT_EQ(report.at("starts"), 3);
  // Two starts of different tunings do not merge.
  ASSERT_EQ(
      cli(tune + " --set sigma_r=3 --shard 2/3 --out " + (f / "other.json"), "2>/dev/null").code,
      0);
  const auto m =
      cli("merge " + out + "/part_1.json " + (f / "other.json") + " " + out + "/part_3.json");
  EXPECT_EQ(m.code, 2) << m.text;
  EXPECT_NE(m.text.find("different tunings"), std::string::npos) << m.text;
}

// --resume trusts complete, schema-valid parts of one job only.
TEST(ScaleSlurm, MergeResumeListsMissingAndInvalidParts) {
  Folder f;
  const std::string dir = f / "parts";
  fs::create_directories(dir);
  auto empty = cli("merge --resume " + dir);
  EXPECT_EQ(empty.code, 2) << empty.text;
  EXPECT_NE(empty.text.find("no complete part"), std::string::npos) << empty.text;
  for (int i : {1, 2, 4, 5, 6}) {
    const std::string shard = std::to_string(i) + "/6";
    ASSERT_EQ(cli("sweep " + kCv1d + kSweep + " --shard " + shard + " --out " + dir + "/part_" +
                      std::to_string(i) + ".json",
                  "2>/dev/null")
                  .code,
              0);
  }
  const std::string p4 = slurp(dir + "/part_4.json");
  std::ofstream(dir + "/part_4.json") << p4.substr(0, p4.size() / 2);  // cut short
  fs::copy_file(dir + "/part_6.json", dir + "/part_5.json", fs::copy_options::overwrite_existing);
  const auto r = cli("merge --resume " + dir);
  EXPECT_EQ(r.code, 0) << r.text;
  EXPECT_NE(r.text.find("3-5\n"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("part_3.json: missing"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("part_4.json: invalid"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("holds shard 6/6, not 5"), std::string::npos) << r.text;
  // A part of another sweep in the folder: refused, not merged.
  ASSERT_EQ(cli("sweep " + kCv1d + " --param sigma_a=1:2:3 --metric rmse --shard 3/6 --out " + dir +
                    "/part_3.json",
                "2>/dev/null")
                .code,
            0);
  const auto mixed = cli("merge --resume " + dir);
  EXPECT_EQ(mixed.code, 2) << mixed.text;
  EXPECT_NE(mixed.text.find("different jobs"), std::string::npos) << mixed.text;
  EXPECT_EQ(cli("merge --resume " + dir + " " + dir + "/part_1.json").code, 2);
  EXPECT_EQ(cli("merge").code, 2);
}

// The same bytes for every --jobs: Monte Carlo, sweep, tune.
TEST(ScaleSlurm, OutputsAreIdenticalForEveryJobs) {
  Folder f;
  std::string first_mc, first_sweep, first_tune;
  for (int jobs : {1, 2, 3}) {
    const std::string j = " --jobs " + std::to_string(jobs);
    const auto mc = cli("run " + kCv1d + " --seeds 1..9 --out " + (f / "mc.json") + j);
    ASSERT_EQ(mc.code, 0) << mc.text;
    const auto sw = cli("sweep " + kCv1d + kSweep + " --out " + (f / "sw.csv") + j);
    ASSERT_EQ(sw.code, 0) << sw.text;
    const auto tu = cli("tune " + kCv1d + " --budget 30 --out " + (f / "tu.json") + j);
    ASSERT_EQ(tu.code, 0) << tu.text;
    const std::string mc_bytes = slurp(f / "mc.json") + mc.text;
    const std::string sw_bytes = slurp(f / "sw.csv") + sw.text;
    const std::string tu_bytes = slurp(f / "tu.json") + tu.text;
    if (jobs == 1) {
      first_mc = mc_bytes;
      first_sweep = sw_bytes;
      first_tune = tu_bytes;
      continue;
    }
    EXPECT_EQ(mc_bytes, first_mc) << jobs;
    EXPECT_EQ(sw_bytes, first_sweep) << jobs;
    EXPECT_EQ(tu_bytes, first_tune) << jobs;
  }
  EXPECT_EQ(cli("run " + kCv1d + " --seeds 1..3 --jobs 0").code, 2);
}

// A real single-node Slurm (Debian's slurm-wlm and munge, scripts/setup-slurm.sh): a 4-task sweep
// array and its merge equal the local sweep byte for byte. Slow (≈ 10 s of scheduling); skips,
// quoting the failing line, where the packages or daemons cannot start (no root, no network).
TEST(ScaleSlurm, RealSlurmArrayEqualsTheLocalSweep) {
  const auto setup = run_command("bash " + kSource + "/scripts/setup-slurm.sh 2>&1");
  if (setup.code != 0) GTEST_SKIP() << "setup-slurm.sh: " << setup.text;
  Folder f;
  const std::string daemons = f / "slurm";
  const auto start =
      run_command("bash " + kSource + "/scripts/slurm/single_node.sh start " + daemons + " 2>&1");
  if (start.code != 0) GTEST_SKIP() << start.text;
  struct Stop {
    std::string cmd;
    ~Stop() { run_command(cmd); }
  } stop{"bash " + kSource + "/scripts/slurm/single_node.sh stop " + daemons + " 2>&1"};
  const std::string env = "SLURM_CONF=" + daemons + "/slurm.conf KFW_CLI=" + std::string(KFW_CLI);
  const std::string out = f / "out";
  const auto o = run_command(env + " bash " + kSource + "/scripts/slurm_submit.sh " + out +
                             " 4 sweep " + kCv1d + kSweep + " 2>&1");
  ASSERT_EQ(o.code, 0) << o.text;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(out + "/merge.log") || !fs::exists(out + "/sweep.json") ||
         run_command(env + " squeue -h 2>&1").text.size() > 0) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline)
        << "the array did not finish in 120 s: " << run_command(env + " squeue 2>&1").text;
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
  ASSERT_EQ(cli("sweep " + kCv1d + kSweep + " --out " + (f / "local.json")).code, 0);
  EXPECT_EQ(slurp(out + "/sweep.json"), slurp(f / "local.json"));
  for (int i = 1; i <= 4; ++i)
    EXPECT_TRUE(fs::exists(out + "/part_" + std::to_string(i) + ".json")) << i;
}

}  // namespace
}  // namespace scale_slurm_cli_test
}  // namespace kfw
