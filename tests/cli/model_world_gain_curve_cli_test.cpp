// Issue 27: the gain curve against a derived scalar, `kfw-cli gain FILE --curve KEY --x DERIVED`
// (sweep KEY, give each point's derived value too): seed 000's k1 against β from the model file
// presets/helicopter.json equals the closed form k1(β) (1e-9).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "common/cli_runner.h"

namespace kfw {
namespace model_world_gain_curve_cli_test {
namespace {

using testing::cli;

const std::string kFile = KFW_SOURCE_DIR "/presets/helicopter.json";

double k1_closed_form(double b) {
  const double p = std::sqrt(b) * (std::sqrt(1 + 0.25 * b) + 0.5 * std::sqrt(b));
  return p / (1 + p);
}

TEST(ModelWorldGainCurveCli, K1AgainstBetaIsTheClosedForm) {
  for (const char* m : {"1", "5"}) {
    auto r =
        cli("gain " + kFile + " --set m=" + m + " --curve Q --x beta --points 25", "2>/dev/null");
    ASSERT_EQ(r.code, 0) << r.text;
    const auto j = nlohmann::json::parse(r.text);
    EXPECT_EQ(j.at("x_quantity"), "derived.beta");
    const auto& q = j.at("x");
    const auto& beta = j.at("x_values");
    const auto& k1 = j.at("gains").at("K.theta.angle");
    ASSERT_EQ(beta.size(), 25u);
    for (std::size_t i = 0; i < beta.size(); ++i) {
      // β = m Ts² Q / R at the preset's Ts = 0.02 s and R = 1.96 deg².
      const double b = std::stod(m) * 0.02 * 0.02 * q[i].get<double>() / 1.96;
      EXPECT_NEAR(beta[i].get<double>(), b, 1e-12 * b) << i;
      EXPECT_NEAR(k1[i].get<double>(), k1_closed_form(b), 1e-9) << "beta " << b;
    }
  }
}

TEST(ModelWorldGainCurveCli, AnUnknownQuantityOrNoCurveIsRefused) {
  auto r = cli("gain " + kFile + " --curve Q --x bta", "2>&1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.text.find("--x: unknown quantity of the steady state 'bta'"), std::string::npos)
      << r.text;
  r = cli("gain " + kFile + " --x beta", "2>&1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.text.find("--x needs --curve KEY"), std::string::npos) << r.text;
}

}  // namespace
}  // namespace model_world_gain_curve_cli_test
}  // namespace kfw
