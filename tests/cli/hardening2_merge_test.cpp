// Hardening round 2 (issue 29): `merge` validates every Monte Carlo part against its schema
// before combining — a type-confused node is refused with the file and the JSON path (before:
// SIGABRT on an uncaught type error, or a silent merge of negative counts, a seed of `true`, a
// time axis that does not increase, or a 1e308 metric that averaged to null) — and honours
// --out with the merged part, which merges again.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <tuple>
#include <vector>

#include "common/cli_runner.h"
#include "common/short_temp_dir.h"

namespace kfw {
namespace {

using nlohmann::json;
using testing::cli;

const std::string kMergeCv1d = std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json";

class MergeSchema : public testing::ShortTempDir {
 protected:
  void SetUp() override {
    ShortTempDir::SetUp();
    for (int s : {1, 2}) {
      auto r = cli("run " + kMergeCv1d + " --seeds 1..4 --shard " + std::to_string(s) +
                   "/2 --set sim.duration=3 --out " + part(s));
      ASSERT_EQ(r.code, 0) << r.text;
    }
  }
  std::string part(int s) const { return dir_ + "/c" + std::to_string(s) + ".json"; }
  json second() const {
    std::ifstream in(part(2));
    return json::parse(in);
  }
  // A sweep of cv1d in two shards: DIR/NAME1.json and DIR/NAME2.json.
  void sweep_shards(const std::string& name) const {
    const std::string grid = " --param sigma_a=0.1:10:4 --metric rmse --set sim.duration=3";
    for (int s : {1, 2}) {
      auto r = cli("sweep " + kMergeCv1d + grid + " --shard " + std::to_string(s) + "/2 --out " +
                   dir_ + "/" + name + std::to_string(s) + ".json");
      ASSERT_EQ(r.code, 0) << r.text;
    }
  }
  // Part 2 edited by `edit`, merged with part 1: exit 2 naming the file and `key`.
  void refused(const std::string& name, const std::function<void(json&)>& edit,
               const std::string& key) {
    json j = second();
    edit(j);
    const std::string p = dir_ + "/" + name + ".json";
    std::ofstream(p) << j.dump();
    auto r = cli("merge " + part(1) + " " + p);
    EXPECT_EQ(r.code, 2) << name << ": " << r.text;
    EXPECT_NE(r.text.find(p + ": " + key), std::string::npos) << name << ": " << r.text;
  }
};

TEST_F(MergeSchema, TypeConfusedNodesAreRefusedNamingTheFileAndKey) {
  refused(
      "version_null", [](json& j) { j["version"] = nullptr; }, "version");
  refused(
      "version_text", [](json& j) { j["version"] = ""; }, "version");
  refused(
      "kind_number", [](json& j) { j["kind"] = 0; }, "kind");
  refused(
      "unit_number", [](json& j) { j["error_unit"] = 2.5; }, "error_unit");
  refused(
      "seed_true", [](json& j) { j["runs"][0]["seed"] = true; }, "runs[0].seed");
  refused(
      "seed_huge", [](json& j) { j["seeds"][0] = 1e308; }, "seeds[0]");
  refused(
      "metric_text", [](json& j) { j["runs"][0]["metrics"]["rmse"] = "x"; },
      "runs[0].metrics.rmse");
}

TEST_F(MergeSchema, InconsistentStatisticsAreRefused) {
  refused(
      "negative_count", [](json& j) { j["nis"][0]["count"][2] = -1; }, "nis[0].count[2]");
  refused(
      "fractional_count", [](json& j) { j["nis"][0]["count"][2] = 1.5; }, "nis[0].count[2]");
  refused(
      "negative_squares", [](json& j) { j["nis"][0]["sum_sq"][2] = -4.0; }, "nis[0].sum_sq[2]");
  refused(
      "time_back", [](json& j) { j["t"][3] = j["t"][2]; }, "t[3]");
  refused(
      "huge_metric", [](json& j) { j["runs"][0]["metrics"]["rmse"] = 1e308; },
      "runs[0].metrics.rmse");
  // A count above the part's runs (was merged: 4294967297 of 2 runs); the three arrays of one
  // length.
  refused(
      "count_above_runs", [](json& j) { j["nees"]["count"][1] = 4294967297LL; },
      "nees.count[1]: 4294967297 is more than the part's 2 runs");
  refused(
      "short_sums", [](json& j) { j["nis"][0]["sum"].erase(0); }, "nis[0].sum: ");
}

// Parts of one run hold the same blocks: a part whose NIS block was emptied merged with one
// that has the channel (exit 0 before); a block renamed in one part names the block and key.
TEST_F(MergeSchema, PartsWithDifferentBlocksAreRefused) {
  json j = second();
  j["nis"] = json::array();
  const std::string p = dir_ + "/no_nis.json";
  std::ofstream(p) << j.dump();
  auto r = cli("merge " + part(1) + " " + p);
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find(p + ": holds nees, error, variance, no nis"), std::string::npos) << r.text;
  json renamed = second();
  renamed["variance"]["name"] = "other";
  const std::string q = dir_ + "/renamed.json";
  std::ofstream(q) << renamed.dump();
  auto s = cli("merge " + part(1) + " " + q);
  EXPECT_EQ(s.code, 2) << s.text;
  EXPECT_NE(s.text.find(q + ": variance: name: 'other'"), std::string::npos) << s.text;
}

TEST_F(MergeSchema, OutWritesTheMergedPartWhichMergesAgain) {
  const std::string all = dir_ + "/all.json";
  auto r = cli("merge " + part(1) + " " + part(2) + " --out " + all, "2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  ASSERT_TRUE(std::filesystem::exists(all));
  auto again = cli("merge " + all, "2>/dev/null");
  ASSERT_EQ(again.code, 0) << again.text;
  EXPECT_EQ(again.text, r.text);  // the same summary from the merged part alone
}

// Part version 2: the preset's content hash and every value; parts of different runs are refused
// naming the key (before, a KF half and a UKF half merged into one summary, exit 0).
TEST_F(MergeSchema, PartsOfDifferentRunsAreRefused) {
  const auto shard2 = [&](const std::string& preset, const std::string& sets,
                          const std::string& out) {
    auto r = cli("run " + preset + " --seeds 1..4 --shard 2/2 --set sim.duration=3" + sets +
                 " --out " + out);
    EXPECT_EQ(r.code, 0) << r.text;
    return out;
  };
  const auto refused = [&](const std::string& other, const std::string& fragment) {
    auto r = cli("merge " + part(1) + " " + other);
    EXPECT_EQ(r.code, 2) << r.text;
    EXPECT_NE(r.text.find(other + ": " + fragment), std::string::npos) << r.text;
  };
  refused(shard2(kMergeCv1d, " --set filter=ukf", dir_ + "/ukf.json"), "values.filter: ");
  refused(shard2(kMergeCv1d, " --set sigma_a=5", dir_ + "/q.json"), "values.sigma_a: 5 differs");
  // The same file content elsewhere is the same preset; an edited one is not.
  const std::string copy = dir_ + "/copy.json";
  std::filesystem::copy_file(kMergeCv1d, copy);
  auto same = cli("merge " + part(1) + " " + shard2(copy, "", dir_ + "/same.json"), "2>&1");
  EXPECT_EQ(same.code, 0) << same.text;
  json edited = json::parse(std::ifstream(kMergeCv1d));
  edited["title"] = "edited between the shards";
  std::ofstream(copy) << edited.dump();
  refused(shard2(copy, "", dir_ + "/edited.json"), "preset_hash: ");
}

TEST_F(MergeSchema, AVersion1PartMergesWithAWarningThatSamenessIsUnchecked) {
  json old = second();
  old["version"] = 1;
  old.erase("preset_hash");
  old.erase("values");
  const std::string p = dir_ + "/old.json";
  std::ofstream(p) << old.dump();
  auto r = cli("merge " + part(1) + " " + p, "2>&1 >/dev/null");
  EXPECT_EQ(r.code, 0) << r.text;
  EXPECT_NE(r.text.find(p + ": a version-1 part records no preset hash or values"),
            std::string::npos)
      << r.text;
}

// Sweep parts: the same schema check (before: a corrupted point was copied into a JSON --out,
// and the message of a wrong type named no file and no key).
TEST_F(MergeSchema, CorruptedSweepPartsAreRefusedNotCopiedThrough) {
  ASSERT_NO_FATAL_FAILURE(sweep_shards("s"));
  const auto edited = [&](const std::string& name, const std::function<void(json&)>& edit) {
    std::ifstream in(dir_ + "/s2.json");
    json j = json::parse(in);
    edit(j);
    const std::string p = dir_ + "/" + name + ".json";
    std::ofstream(p) << j.dump();
    return p;
  };
  const std::string out = dir_ + "/merged.json";
  for (const auto& [name, edit, key] :
       std::vector<std::tuple<std::string, std::function<void(json&)>, std::string>>{
           {"at_object",
            [](json& j) {
              j["points"][0]["at"] = json::array({21.5, json::object()});
            },
            "points[0].at"},
           {"at_null", [](json& j) { j["points"][0]["at"] = nullptr; }, "points[0].at"},
           {"index_negative", [](json& j) { j["points"][0]["index"] = -1; }, "points[0].index"},
           {"kind_number", [](json& j) { j["kind"] = 0; }, "kind"},
           {"n_huge", [](json& j) { j["axes"][0]["n"] = 1e308; }, "axes[0].n"},
           // Coordinates and indices against the part's own grid (merged before, copied into
           // --out): off the grid, another shard's point, a point twice, a grid of another size.
           {"off_grid", [](json& j) { j["points"][0]["at"][0] = 2.5; }, "points[0].at[0]: 2.5"},
           {"other_shard", [](json& j) { j["points"][0]["index"] = 0; }, "points[0].index"},
           {"twice", [](json& j) { j["points"].push_back(j["points"][0]); },
            "points[2].index: point 1 given twice"},
           {"total", [](json& j) { j["total_points"] = 5; }, "total_points: 5"}}) {
    const std::string p = edited(name, edit);
    auto r = cli("merge " + dir_ + "/s1.json " + p + " --out " + out);
    EXPECT_EQ(r.code, 2) << name << ": " << r.text;
    EXPECT_NE(r.text.find(p + ": " + key), std::string::npos) << name << ": " << r.text;
    EXPECT_FALSE(std::filesystem::exists(out)) << name;
  }
}

// A point whose metric is undefined (null, as a sweep writes NaN) merges as undefined (before:
// "a part is malformed ([json.exception.type_error.302] …)", no file, no key).
TEST_F(MergeSchema, ASweepPointWithANullValueMergesAsUndefined) {
  ASSERT_NO_FATAL_FAILURE(sweep_shards("n"));
  json j = json::parse(std::ifstream(dir_ + "/n2.json"));
  j["points"][0]["value"] = nullptr;
  std::ofstream(dir_ + "/n2.json") << j.dump();
  auto r = cli("merge " + dir_ + "/n1.json " + dir_ + "/n2.json", "2>/dev/null");
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_EQ(json::parse(r.text).at("points_defined"), 3) << r.text;
}

TEST_F(MergeSchema, SweepPartsOfAnEditedPresetAreRefused) {
  const std::string copy = dir_ + "/sweep_preset.json";
  std::filesystem::copy_file(kMergeCv1d, copy);
  const std::string grid = " --param sigma_a=0.1:10:4 --metric rmse --set sim.duration=3";
  auto a = cli("sweep " + copy + grid + " --shard 1/2 --out " + dir_ + "/w1.json");
  ASSERT_EQ(a.code, 0) << a.text;
  json edited = json::parse(std::ifstream(kMergeCv1d));
  edited["title"] = "edited between the shards";
  std::ofstream(copy) << edited.dump();
  auto b = cli("sweep " + copy + grid + " --shard 2/2 --out " + dir_ + "/w2.json");
  ASSERT_EQ(b.code, 0) << b.text;
  auto r = cli("merge " + dir_ + "/w1.json " + dir_ + "/w2.json");
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find("w2.json: preset_hash: differs"), std::string::npos) << r.text;
}

}  // namespace
}  // namespace kfw
