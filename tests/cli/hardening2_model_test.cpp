// Hardening round 2 (issue 29): what a number in a model file can make huge is bounded
// (docs/limits.md). Loading is linear in the number of entries (a 300-state diagonal model took
// 74 s; bench/make_diagonal_model.py writes the benchmark's), states and channels are limited, a
// channel's `every` is at most 10^6 and its m-step model is computed by squaring (10^15 hung
// `gain`), and a model simulation's rows are bounded by memory (36 M rows ran into the OOM killer).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/cli_runner.h"
#include "common/short_temp_dir.h"

namespace kfw {
namespace {

using nlohmann::json;
using testing::cli;

const std::string kLimitsCv1d = std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json";

class ModelLimits : public testing::ShortTempDir {
 protected:
  std::string diagonal(int n) const {
    const std::string p = dir_ + "/diag" + std::to_string(n) + ".json";
    auto r = testing::run_command("python3 " + std::string(KFW_SOURCE_DIR) +
                                  "/bench/make_diagonal_model.py " + std::to_string(n) + " > " + p);
    EXPECT_EQ(r.code, 0) << r.text;
    return p;
  }
  json cv1d() const {
    std::ifstream in(kLimitsCv1d);
    return json::parse(in);
  }
};

TEST_F(ModelLimits, ALargeDiagonalModelLoadsAndTooManyStatesAreRefused) {
  auto ok = cli("params " + diagonal(300), "2>&1 >/dev/null");
  EXPECT_EQ(ok.code, 0) << ok.text;
  json big = json::parse(std::ifstream(diagonal(2)));
  big["model"]["states"] = json::array();
  for (int i = 0; i < 1001; ++i)
    big["model"]["states"].push_back("s" + std::to_string(i));
  auto r = cli("params " + write("many.json", big.dump()));
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find("model.states: 1001 states"), std::string::npos) << r.text;
}

TEST_F(ModelLimits, EveryIsBoundedAndItsSteadyStateIsComputedBySquaring) {
  json j = cv1d();
  auto& ch = j["model"]["measurements"].begin().value();
  ch["every"] = 1000000000000000LL;
  auto r = cli("gain " + write("huge.json", j.dump()));
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find(".every: 1000000000000000 is more than the limit"), std::string::npos)
      << r.text;
  ch["every"] = 1000000;
  auto g = testing::run_command("timeout 20 " + std::string(KFW_CLI) + " gain " +
                                write("max.json", j.dump()) + " 2>&1");
  EXPECT_EQ(g.code, 0) << g.text;
  EXPECT_NE(g.text.find("\"every\": 1000000"), std::string::npos) << g.text;
  // m = 7 by squaring equals the 7-step model written out (F⁷ and Σ_{i<7} Fⁱ Q Fⁱᵀ, summed here
  // step by step) as a model updated at every step.
  ch["every"] = 7;
  auto seven = cli("gain " + write("seven.json", j.dump()), "2>/dev/null");
  ASSERT_EQ(seven.code, 0) << seven.text;
  const double dt = j["parameters"]["sim.dt"]["value"].get<double>();
  const double sa = j["parameters"]["sigma_a"]["value"].get<double>();
  const double q[2][2] = {{std::pow(dt, 4) / 4 * sa * sa, std::pow(dt, 3) / 2 * sa * sa},
                          {std::pow(dt, 3) / 2 * sa * sa, dt * dt * sa * sa}};
  double Q7[2][2] = {{0, 0}, {0, 0}};
  for (int i = 0; i < 7; ++i) {  // Fⁱ = [[1, i dt], [0, 1]]
    const double f = i * dt;
    const double a = q[0][0] + 2 * f * q[0][1] + f * f * q[1][1], b = q[0][1] + f * q[1][1];
    Q7[0][0] += a;
    Q7[0][1] += b;
    Q7[1][0] += b;
    Q7[1][1] += q[1][1];
  }
  const auto num = [](double v) {
    std::ostringstream os;
    os.precision(17);
    os << v;
    return os.str();
  };
  ch["every"] = 1;
  j["model"]["process"]["F"] =
      json::array({json::array({"1", num(7 * dt)}), json::array({"0", "1"})});
  j["model"]["process"]["Q"] = json::array(
      {json::array({num(Q7[0][0]), num(Q7[0][1])}), json::array({num(Q7[1][0]), num(Q7[1][1])})});
  auto one = cli("gain " + write("written.json", j.dump()), "2>/dev/null");
  ASSERT_EQ(one.code, 0) << one.text;
  const json a = json::parse(seven.text), b = json::parse(one.text);
  for (const char* k : {"K.x.z", "K.v.z", "P_pred.x", "P_pred.v"})
    EXPECT_NEAR(a.at(k).get<double>(), b.at(k).get<double>(),
                1e-9 * std::abs(b.at(k).get<double>()))
        << k;
}

TEST_F(ModelLimits, ASimulationTooLongForMemoryIsRefusedWithTheLimit) {
  auto r = testing::run_command("KFW_MEMORY_LIMIT=100000000 " + std::string(KFW_CLI) + " run " +
                                kLimitsCv1d + " --set sim.duration=3600 --set sim.dt=0.0001 2>&1");
  EXPECT_EQ(r.code, 2) << r.text;
  EXPECT_NE(r.text.find(kLimitsCv1d + ": sim.duration / sim.dt: 36000001 rows; a simulation "
                                      "of this model may have at most"),
            std::string::npos)
      << r.text;
  EXPECT_NE(r.text.find("95.4 MB memory limit"), std::string::npos) << r.text;
}

}  // namespace
}  // namespace kfw
