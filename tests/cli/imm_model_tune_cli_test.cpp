// Issue 28: tuning for a consistency target (rmse+nis, rmse+anis) says when it costs more than 10 %
// of the metric it ranks against the start, with both points (radome's IMM: NIS/dof = 1 only by a
// worse filter), and says nothing when it does not.
#include <gtest/gtest.h>

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
  const std::string args = "tune " + kPresetDir + "radome.json --budget 40";
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

}  // namespace
}  // namespace kfw
