// kfw-cli on a model file: the gain curve (`gain --curve KEY`) is the DARE gain at every point,
// passes through the live operating point, and refuses a key that is not a continuous parameter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "common/cli_runner.h"

namespace kfw {
namespace {

const std::string kCv = std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json";

TEST(ModelCli, GainCurvePassesThroughTheOperatingPoint) {
  const auto c =
      testing::cli("gain " + kCv + " --curve sigma_r --points 7 --set sigma_a=2", "2>/dev/null");
  ASSERT_EQ(c.code, 0) << c.text;
  const auto j = nlohmann::json::parse(c.text);
  EXPECT_EQ(j["parameter"], "sigma_r");
  EXPECT_TRUE(j["log"].get<bool>());
  ASSERT_EQ(j["x"].size(), 7u);
  ASSERT_EQ(j["gains"]["K.x.z"].size(), 7u);
  // Position gain falls as the measurement noise grows.
  const auto& k = j["gains"]["K.x.z"];
  for (std::size_t i = 1; i < k.size(); ++i)
    EXPECT_LT(k[i].get<double>(), k[i - 1].get<double>());
  // The operating point is `gain` at the live values.
  const auto g = testing::cli("gain " + kCv + " --set sigma_a=2", "2>/dev/null");
  ASSERT_EQ(g.code, 0) << g.text;
  const auto gj = nlohmann::json::parse(g.text);
  EXPECT_EQ(j["at"]["value"].get<double>(), 2.0 /* σ_r's preset value */);
  EXPECT_EQ(j["at"]["gains"]["K.x.z"].get<double>(), gj["K.x.z"].get<double>());
  EXPECT_EQ(j["at"]["gains"]["K.v.z"].get<double>(), gj["K.v.z"].get<double>());
}

TEST(ModelCli, GainCurveRefusesAKeyThatIsNotAContinuousParameter) {
  for (const char* key : {"sigma_b", "sim.seed", "filter"}) {
    const auto c = testing::cli("gain " + kCv + " --curve " + key);
    EXPECT_EQ(c.code, 2) << key << ": " << c.text;
    EXPECT_NE(c.text.find("--curve"), std::string::npos) << c.text;
  }
  const auto c = testing::cli("gain " + kCv + " --curve sigma_b");
  EXPECT_NE(c.text.find("did you mean 'sigma_a'"), std::string::npos) << c.text;
}

TEST(ModelCli, NonlinearModelHasNoGainCurve) {
  const auto c = testing::cli("gain " + std::string(KFW_SOURCE_DIR) +
                              "/presets/models/pendulum.json --curve " + "q");
  EXPECT_NE(c.code, 0) << c.text;
  EXPECT_EQ(std::count(c.text.begin(), c.text.end(), '\n'), 1) << c.text;
}

}  // namespace
}  // namespace kfw
