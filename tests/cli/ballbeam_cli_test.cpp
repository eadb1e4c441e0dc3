// kfw-cli on the ballbeam preset: `gain` prints the closed-form and DARE α-β, `run` prints the
// paper-reproduction metrics and warns when the ball leaves the beam, bad --set values fail with
// the key in the message.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <string>

namespace {

struct Output {
  int status = -1;
  std::string text;
};

// `redirect` picks the stream(s) read: both by default, "2>/dev/null" stdout only,
// "2>&1 >/dev/null" stderr only.
Output cli(const std::string& args, const std::string& redirect = "2>&1") {
  const std::string cmd = std::string(KFW_CLI) + " " + args + " " + redirect;
  Output out;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe))
    out.text += buf.data();
  out.status = pclose(pipe);
  return out;
}

std::string preset() {
  return std::string(KFW_SOURCE_DIR) + "/presets/ballbeam.json";
}

TEST(BallbeamCli, GainPrintsClosedFormAndDare) {
  const Output o = cli("gain " + preset());
  ASSERT_EQ(o.status, 0) << o.text;
  const auto j = nlohmann::json::parse(o.text);
  EXPECT_NEAR(j.at("lambda").get<double>(), 0.0354, 5e-5);
  EXPECT_NEAR(j.at("alpha").get<double>(), 0.2335, 1e-4);  // SPEC §3; Table 1: 0.234
  EXPECT_NEAR(j.at("beta").get<double>(), 0.0310, 1e-4);   // Table 1: 0.031
  EXPECT_NEAR(j.at("alpha_dare").get<double>(), j.at("alpha").get<double>(), 1e-8);
  EXPECT_NEAR(j.at("beta_dare").get<double>(), j.at("beta").get<double>(), 1e-8);
}

TEST(BallbeamCli, RunShowsDetectionOnNearNoiseFreeAndOffDegraded) {
  const Output on = cli("run " + preset(), "2>/dev/null");
  ASSERT_EQ(on.status, 0) << on.text;
  const auto j = nlohmann::json::parse(on.text);
  for (const char* k : {"rmse", "tracking_rmse", "alpha", "beta", "missing_fraction"})
    ASSERT_TRUE(j.contains(k)) << k;
  EXPECT_LT(5 * j.at("tracking_excess_detect_on").get<double>(),
            j.at("tracking_excess_detect_off").get<double>());
  const Output off = cli("run " + preset() + " --set detection=0", "2>/dev/null");
  ASSERT_EQ(off.status, 0) << off.text;
  const auto k = nlohmann::json::parse(off.text);
  EXPECT_GT(k.at("rmse").get<double>(), 5 * j.at("rmse").get<double>());
}

TEST(BallbeamCli, BallLeavingTheBeamIsAWarningAndAMetric) {
  const std::string args = "run " + preset() + " --set sim.burst=100";
  const Output warnings = cli(args, "2>&1 >/dev/null");
  EXPECT_EQ(warnings.status, 0) << warnings.text;
  EXPECT_NE(warnings.text.find("kfw-cli: warning: ball off the beam"), std::string::npos)
      << warnings.text;
  EXPECT_NE(warnings.text.find("(detection on)"), std::string::npos) << warnings.text;
  const Output metrics = cli(args, "2>/dev/null");
  ASSERT_EQ(metrics.status, 0);
  const auto j = nlohmann::json::parse(metrics.text);
  ASSERT_TRUE(j.at("left_beam_at_s").is_number());
  EXPECT_GT(j.at("left_beam_at_s").get<double>(), 1.0);  // after the set-point step
  // The noise-free ball stays on: no number (never NaN or null), said why when listed.
  EXPECT_FALSE(j.contains("left_beam_at_s_noise_free")) << j;
  if (j.contains("undefined")) {
    EXPECT_TRUE(j["undefined"].contains("left_beam_at_s_noise_free")) << j["undefined"];
  }
  EXPECT_EQ(j.at("diverged").get<double>(), 0.0);
  EXPECT_EQ(j.at("fell").get<double>(), 1.0);  // a result, exit 0
  // The default run keeps the ball on the beam; only the run without the circuit leaves the
  // small-angle range.
  const std::string calm = cli("run " + preset(), "2>&1 >/dev/null").text;
  EXPECT_EQ(calm.find("off the beam"), std::string::npos) << calm;
  EXPECT_NE(calm.find("(detection off); the model"), std::string::npos) << calm;
}

TEST(BallbeamCli, BadValuesNameTheKey) {
  for (const char* set : {"Ts=0", "R=-1", "sim.contact_loss_rate=2"}) {
    const Output o = cli("run " + preset() + " --set " + set);
    EXPECT_NE(o.status, 0) << set;
    const std::string key = std::string(set).substr(0, std::string(set).find('='));
    EXPECT_NE(o.text.find(key), std::string::npos) << o.text;
  }
}

}  // namespace
