// The fixtures of tests/fixtures/ (saved by commit d410b8e) through kfw-cli: `merge` reads every
// Monte Carlo and sweep part of version 1, and `metrics` lists, for each seed preset, the keys it
// listed then.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/cli_runner.h"
#include "common/fixture_metric_changes.h"

namespace format_fixtures_cli_test {
namespace {

namespace fs = std::filesystem;

using kfw::testing::cli;

const fs::path kFixtureDir = fs::path(KFW_SOURCE_DIR) / "tests" / "fixtures";
const std::vector<std::string> kSeedPresets = {"helicopter", "broad_imu", "radome", "ballbeam",
                                               "underwater"};

std::string file_text(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

// The first column of each line.
std::vector<std::string> first_column(const std::string& text) {
  std::vector<std::string> keys;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) keys.push_back(line.substr(0, line.find('\t')));
  }
  return keys;
}

fs::path scratch_dir() {
  const fs::path d = fs::temp_directory_path() / ("kfw_fixtures_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

TEST(FormatFixturesCli, MetricsListsTheKeysEachSeedPresetListedAtTheFixturesCommit) {
  for (const auto& name : kSeedPresets) {
    SCOPED_TRACE(name);
    const auto r =
        cli("metrics " + std::string(KFW_SOURCE_DIR) + "/presets/" + name + ".json", "2>/dev/null");
    ASSERT_EQ(r.code, 0) << r.text;
    const auto saved = first_column(file_text(kFixtureDir / "metrics" / (name + ".tsv")));
    EXPECT_GT(saved.size(), 10u);
    // The differences CHANGES.md lists (common/fixture_metric_changes.h), and nothing else.
    EXPECT_EQ(kfw::testing::compare_with_changes(first_column(r.text), saved,
                                                 kfw::testing::fixture_metric_changes(name)),
              "");
  }
}

TEST(FormatFixturesCli, MergeReadsEveryMonteCarloPartOfVersion1) {
  for (const auto& name : kSeedPresets) {
    if (name == "broad_imu") continue;  // a preset with a data file has no Monte Carlo part
    SCOPED_TRACE(name);
    const fs::path part = kFixtureDir / "montecarlo_v1" / (name + ".json");
    const auto r = cli("merge " + part.string(), "2>/dev/null");
    ASSERT_EQ(r.code, 0) << r.text;
    const auto summary = nlohmann::json::parse(r.text, nullptr, false);
    ASSERT_TRUE(summary.is_object()) << r.text;
    const auto saved = nlohmann::json::parse(file_text(part));
    EXPECT_EQ(summary.at("scenario"), saved.at("scenario"));
    EXPECT_EQ(summary.at("seeds"), 2);
    EXPECT_EQ(summary.at("completed"), 2);
    EXPECT_EQ(summary.at("metrics").at("rmse").at("n"), 2);
    EXPECT_TRUE(summary.at("consistency").contains("anees"));
  }
}

TEST(FormatFixturesCli, MergeReadsEverySweepPartOfVersion1AndWritesItBackUnchanged) {
  const fs::path dir = scratch_dir();
  for (const auto& name : kSeedPresets) {
    SCOPED_TRACE(name);
    const fs::path part = kFixtureDir / "sweep_v1" / (name + ".json");
    const fs::path merged = dir / (name + ".json");
    const auto r = cli("merge " + part.string() + " --out " + merged.string(), "2>/dev/null");
    ASSERT_EQ(r.code, 0) << r.text;
    const auto summary = nlohmann::json::parse(r.text, nullptr, false);
    ASSERT_TRUE(summary.is_object()) << r.text;
    EXPECT_EQ(summary.at("metric"), "rmse");
    EXPECT_EQ(summary.at("points"), 3);
    EXPECT_EQ(summary.at("points_defined"), 3);
    // One shard of one is the whole sweep: merged, it is the same document byte for byte.
    EXPECT_EQ(file_text(merged), file_text(part));
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace format_fixtures_cli_test
