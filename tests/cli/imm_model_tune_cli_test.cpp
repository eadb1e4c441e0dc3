// Issue 28: tuning for a consistency target (rmse+nis, rmse+anis) says when it costs more than 10 %
// of the metric it ranks against the start, with both points (radome's IMM: NIS/dof = 1 only by a
// worse filter), and says nothing when it does not.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/cli_runner.h"

namespace kfw {
namespace {

using testing::cli;

const std::string kPresetDir = KFW_SOURCE_DIR "/presets/";

nlohmann::json stdout_json(const std::string& args) {
  return nlohmann::json::parse(cli(args, "2>/dev/null").text, nullptr, false);
}

TEST(ImmModelTuneCli, AConsistencyTargetThatCostsTheMetricIsReported) {
  // radome with its noise keys in one scale group (as the built-in's preset had them; the
  // shipped file has none since its default objective became the refraction error), tuned for
  // the consistency target: NIS/dof = 1 only by a worse filter.
  auto preset = nlohmann::ordered_json::parse(std::ifstream(kPresetDir + "radome.json"));
  for (const char* k : {"Q", "R", "R_range"})
    preset["parameters"][k]["scale_group"] = "noise";
  const auto dir =
      std::filesystem::temp_directory_path() / ("kfw_imm_tune_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "radome_grouped.json").string();
  std::ofstream(path) << preset.dump(2);
  const std::string args = "tune " + path + " --objective rmse+nis --budget 40";
  const auto all = cli(args);
  ASSERT_EQ(all.code, 0) << all.text;
  EXPECT_NE(all.text.find("warning: meeting the consistency target costs "), std::string::npos)
      << all.text;
  EXPECT_NE(all.text.find("of rmse against the start: start rmse "), std::string::npos);
  const auto j = stdout_json(args);
  ASSERT_FALSE(j.is_discarded());
  const auto& t = j["trade_off"];
  EXPECT_EQ(t["metric"], "rmse");
  EXPECT_TRUE(t["costly"].get<bool>());
  EXPECT_GT(t["cost"].get<double>(), 0.10);
  EXPECT_DOUBLE_EQ(t["value"].get<double>(), j["value"].get<double>());
  EXPECT_DOUBLE_EQ(t["start_value"].get<double>(), j["start_value"].get<double>());
  EXPECT_NEAR(t["nis_mean"].get<double>(), 1.0, 0.05);
  std::filesystem::remove_all(dir);
}

TEST(ImmModelTuneCli, NoReportWhenConsistencyIsFreeOrNotAsked) {
  // gyro_bias: rmse+nis improves the RMSE as well.
  auto r = cli("tune " + kPresetDir + "models/gyro_bias.json --objective rmse+nis");
  ASSERT_EQ(r.code, 0) << r.text;
  EXPECT_EQ(r.text.find("meeting the consistency target"), std::string::npos) << r.text;
  auto j = stdout_json("tune " + kPresetDir + "models/gyro_bias.json --objective rmse+nis");
  EXPECT_FALSE(j["trade_off"]["costly"].get<bool>());
  // A plain metric has no consistency target to report on.
  j = stdout_json("tune " + kPresetDir + "models/cv_imm.json --objective rmse --budget 30");
  ASSERT_FALSE(j.is_discarded());
  EXPECT_FALSE(j.contains("trade_off"));
}

// Radome's default objective is the one its file declares (the largest refraction error, STAGE),
// and its default tune leaves it no worse than the preset's values (the combined
// objective made it 0.41° → 0.73° worst case before issue 28).
TEST(ImmModelTuneCli, RadomesDefaultTuneKeepsTheRefractionError) {
  const auto all = cli("tune " + kPresetDir + "radome.json --budget 30");
  ASSERT_EQ(all.code, 0) << all.text;
  // The objective reads truth: the innovations' whiteness does not make it untrustworthy.
  EXPECT_EQ(all.text.find("not trustworthy"), std::string::npos) << all.text;
  const auto j = nlohmann::json::parse(all.text.substr(all.text.find("{\n")), nullptr, false);
  ASSERT_FALSE(j.is_discarded());
  EXPECT_EQ(j["objective"], "refraction_err_max_deg");
  EXPECT_EQ(j["objective_from"], "declared by the preset (default_objective)");
  EXPECT_LE(j["value"].get<double>(), j["start_value"].get<double>());
  std::string sets;
  for (const auto& [k, v] : j["params"].items())
    sets += " --set " + k + "=" + nlohmann::json(v.get<double>()).dump();
  const auto start = stdout_json("run " + kPresetDir + "radome.json");
  const auto tuned = stdout_json("run " + kPresetDir + "radome.json" + sets);
  ASSERT_FALSE(start.is_discarded() || tuned.is_discarded());
  // The paper's figure is the largest error (within 0.5°, Fig. 4): that is what the file tunes
  // (tuning the RMS instead made the largest error worse, 0.304° → 0.353°).
  EXPECT_LE(tuned["refraction_err_max_deg"].get<double>(),
            start["refraction_err_max_deg"].get<double>() * (1 + 1e-9));
  EXPECT_LT(start["refraction_err_max_deg"].get<double>(), 0.5);  // seed 001 Fig. 4
}

}  // namespace
}  // namespace kfw
