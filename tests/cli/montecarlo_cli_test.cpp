// kfw-cli run --seeds: the summary (JSON and table), refusals (--data, a preset with a data file,
// --shard without --out), shards merged by `kfw-cli merge` equal the unsharded summary, and
// --out-dir writes one estimates file per seed.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "common/cli_runner.h"

namespace {

namespace fs = std::filesystem;

using kfw::testing::cli;

const std::string kCv1d = std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json";
const std::string kShort = " --set sim.duration=3";

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("kfw_mc_" + name + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(MonteCarloCli, SummarisesEveryMetricOverTheSeeds) {
  const auto o = cli("run " + kCv1d + " --seeds 1..5" + kShort, "2>/dev/null");
  ASSERT_EQ(o.code, 0) << o.text;
  const auto j = nlohmann::json::parse(o.text);
  EXPECT_EQ(j.at("seeds"), 5);
  EXPECT_EQ(j.at("completed"), 5);
  const auto& rmse = j.at("metrics").at("rmse");
  EXPECT_EQ(rmse.at("n"), 5);
  EXPECT_LE(rmse.at("min").get<double>(), rmse.at("mean").get<double>());
  EXPECT_GE(rmse.at("max").get<double>(), rmse.at("mean").get<double>());
  EXPECT_GT(rmse.at("sd").get<double>(), 0.0);
  EXPECT_EQ(j.at("consistency").at("anees").at("runs"), 5);
  EXPECT_FALSE(j.contains("steps"));  // the per-step arrays go to --metrics

  const auto t = cli("run " + kCv1d + " --seeds 1..5 --table" + kShort, "2>/dev/null");
  ASSERT_EQ(t.code, 0) << t.text;
  EXPECT_NE(t.text.find("5 seeds, 5 completed"), std::string::npos) << t.text;
  EXPECT_NE(t.text.find("ANEES (2 dof, 5 runs)"), std::string::npos) << t.text;
}

TEST(MonteCarloCli, SeedsAreRefusedWithDataFilesAndBadSets) {
  EXPECT_EQ(cli("run " + kCv1d + " --seeds 1..3 --data x.csv").code, 2);
  const auto broad = cli("run broad_imu --seeds 1..3");
  EXPECT_EQ(broad.code, 2) << broad.text;
  EXPECT_NE(broad.text.find("--seeds simulates"), std::string::npos) << broad.text;
  EXPECT_EQ(cli("run " + kCv1d + " --seeds 5..1").code, 2);
  EXPECT_EQ(cli("run " + kCv1d + " --seeds 1..3 --shard 1/2").code, 2);  // no --out
  EXPECT_EQ(cli("run " + kCv1d + " --shard 1/2").code, 2);               // no --seeds
  EXPECT_EQ(cli("run " + kCv1d + " --seeds 1,2000000").code, 2);         // outside sim.seed
}

TEST(MonteCarloCli, MergedShardsEqualTheUnshardedRun) {
  const fs::path dir = temp_dir("merge");
  const auto whole =
      cli("run " + kCv1d + " --seeds 1..7" + kShort + " --metrics " + (dir / "whole.json").string(),
          "2>/dev/null");
  ASSERT_EQ(whole.code, 0) << whole.text;
  std::string parts;
  for (int i = 1; i <= 3; ++i) {
    const std::string part = (dir / ("part_" + std::to_string(i) + ".json")).string();
    const auto o = cli("run " + kCv1d + " --seeds 1..7" + kShort + " --shard " + std::to_string(i) +
                       "/3 --out " + part);
    ASSERT_EQ(o.code, 0) << o.text;
    parts += " " + part;
  }
  const auto m =
      cli("merge" + parts + " --metrics " + (dir / "merged.json").string(), "2>/dev/null");
  ASSERT_EQ(m.code, 0) << m.text;
  auto read = [&](const std::string& name) {
    std::ifstream in(dir / name);
    return nlohmann::json::parse(in);
  };
  const auto a = read("whole.json"), b = read("merged.json");
  for (const auto& [k, v] : a.at("metrics").items()) {
    for (const char* f : {"mean", "sd", "min", "max"}) {
      const double x = v.at(f), y = b.at("metrics").at(k).at(f);
      EXPECT_LE(std::abs(x - y), 1e-12 * std::max(std::abs(x), std::abs(y))) << k << " " << f;
    }
  }
  const auto& sa = a.at("steps").at("anees");
  const auto& sb = b.at("steps").at("anees");
  ASSERT_EQ(sa.size(), 31u);
  for (std::size_t k = 0; k < sa.size(); ++k) {
    const double x = sa[k], y = sb[k];
    EXPECT_LE(std::abs(x - y), 1e-12 * std::abs(x)) << "step " << k;
  }
  // A shard missing, or a file of no known kind, is refused (exit 2).
  const auto missing = cli("merge " + (dir / "part_1.json").string());
  EXPECT_EQ(missing.code, 2);
  EXPECT_NE(missing.text.find("shard 2/3 is missing"), std::string::npos) << missing.text;
  std::ofstream(dir / "other.json") << R"({"kind": "bogus"})";
  const auto bogus = cli("merge " + (dir / "other.json").string());
  EXPECT_EQ(bogus.code, 2);
  EXPECT_NE(bogus.text.find("other.json: kind"), std::string::npos) << bogus.text;
  fs::remove_all(dir);
}

TEST(MonteCarloCli, OutDirWritesOneEstimatesFilePerSeed) {
  const fs::path dir = temp_dir("outdir");
  const auto o = cli("run " + kCv1d + " --seeds 2,4" + kShort + " --out-dir " + dir.string());
  ASSERT_EQ(o.code, 0) << o.text;
  EXPECT_TRUE(fs::is_regular_file(dir / "seed_2.csv"));
  EXPECT_TRUE(fs::is_regular_file(dir / "seed_4.csv"));
  EXPECT_FALSE(fs::exists(dir / "seed_3.csv"));
  EXPECT_EQ(cli("run " + kCv1d + " --seeds 2,4 --out-dir " + (dir / "nope").string()).code, 2);
  fs::remove_all(dir);
}

}  // namespace
