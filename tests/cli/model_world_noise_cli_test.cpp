// Issue 27 — `kfw-cli noise`, the one noise command of every scenario and model file: the
// helicopter's output as before, a model file that links its columns, one that links none
// (exit 2, the key to add) and a bad `noise_param` (exit 2, file and key).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/bad_input.h"

// A namespace of its own: in a unity batch, helper names stay apart from the neighbours'.
namespace kfw::model_world_noise_cli {
namespace {

using Json = nlohmann::ordered_json;
using testing::cli;

const std::string kHeliLog = KFW_SOURCE_DIR "/data/helicopter.csv";

class NoiseCli : public testing::BadInput {
 protected:
  // presets/models/NAME.json with one edit applied to its JSON, written as FILE.
  std::string model(const std::string& file_name, const std::function<void(Json&)>& edit,
                    const std::string& name) {
    Json j = Json::parse(source("presets/models/" + name + ".json"));
    edit(j);
    return file(file_name, j.dump(2));
  }
  // `kfw-cli noise ARGS` that succeeds: its JSON (stdout only).
  static Json noise(const std::string& args) {
    const auto o = cli("noise " + args, "2>/dev/null");
    EXPECT_EQ(o.code, 0) << args << " → " << o.text;
    return o.code == 0 ? Json::parse(o.text) : Json();
  }
};

std::vector<std::string> keys(const Json& j) {
  std::vector<std::string> k;
  for (const auto& [key, value] : j.items())
    k.push_back(key);
  return k;
}

// presets/helicopter.json is a model file since issue 27 (the built-in it replaced printed the same
// JSON text, checked when the generic command landed): the seed preset and the minimal example
// helicopter_indirect.json link the same columns to the same keys.
TEST_F(NoiseCli, TheHelicopterPrintsTheSameKeysAndTheModelFileTheSameValues) {
  const Json preset = noise(preset_path("helicopter") + " --data " + kHeliLog);
  const std::vector<std::string> expected = {"fs_hz",      "band",        "Q_suggested",
                                             "sigma_gyro", "R_suggested", "sigma_angle"};
  EXPECT_EQ(keys(preset), expected);
  EXPECT_EQ(preset["band"], "above half of Nyquist");
  const Json file = noise(std::string(KFW_SOURCE_DIR) +
                          "/presets/models/helicopter_indirect.json --data " + kHeliLog);
  EXPECT_EQ(keys(file), expected);
  for (const auto& k : expected) {
    if (k == "band") continue;
    const double a = file[k].get<double>(), b = preset[k].get<double>();
    EXPECT_LE(std::abs(a - b), 1e-12 * std::abs(b)) << k << ": " << a << " vs " << b;
  }
}

TEST_F(NoiseCli, AModelFileWithAWorldGetsItsSimulatedSigmasBack) {
  // gyro_bias.json: the world's gyro σ_g = 0.005 rad/s (the filter's input, "as": "sigma") and
  // angle σ_a = 0.01 rad; 6000 samples per seed (600 s), within 6 % each (seeds 1..3 measured
  // within 2.5 %).
  for (int seed : {1, 2, 3}) {
    SCOPED_TRACE(seed);
    const Json j = noise(std::string(KFW_SOURCE_DIR) +
                         "/presets/models/gyro_bias.json --set sim.duration=600 --set sim.seed=" +
                         std::to_string(seed));
    EXPECT_EQ(keys(j), (std::vector<std::string>{"fs_hz", "band", "sigma_g_suggested", "sigma_gyro",
                                                 "sigma_a_suggested", "sigma_angle"}));
    EXPECT_NEAR(j["sigma_g_suggested"].get<double>(), 0.005, 0.06 * 0.005);
    EXPECT_NEAR(j["sigma_a_suggested"].get<double>(), 0.01, 0.06 * 0.01);
    EXPECT_EQ(j["sigma_g_suggested"], j["sigma_gyro"]);  // σ_g is the gyro's σ itself
  }
}

TEST_F(NoiseCli, AFileThatLinksNothingSaysWhichKeyToAdd) {
  const auto path = std::string(KFW_SOURCE_DIR) + "/presets/models/cv1d.json";
  expect_refused("noise " + path, 2,
                 {"cv1d.json: no column's noise is linked to a parameter: add \"noise_param\"",
                  "model.measurements.NAME.noise_param", "model.inputs[i].noise_param"},
                 false);
}

TEST_F(NoiseCli, ABadNoiseParamIsRefusedWithFileAndKey) {
  const auto unknown = model(
      "unknown.json", [](Json& j) { j["model"]["measurements"]["angle"]["noise_param"] = "RR"; },
      "helicopter_indirect");
  expect_refused("noise " + unknown, 2,
                 {"unknown.json: model.measurements.angle.noise_param: unknown parameter 'RR' "
                  "(did you mean 'R'?)"},
                 false);
  const auto v1 = model(
      "v1.json", [](Json& j) { j["model"]["version"] = 1; }, "helicopter_indirect");
  expect_refused("noise " + v1, 2,
                 {"v1.json: model.inputs[0].noise_param: a version-2 key: set \"version\": 2"},
                 false);
  const auto independent = model(
      "independent.json",
      [](Json& j) { j["model"]["measurements"]["angle"]["noise_param"] = "gamma"; },
      "helicopter_indirect");
  expect_refused("run " + independent, 2,
                 {"independent.json: model.measurements.angle.noise_param: "
                  "model.measurements.angle.R[0][0] = \"R\" does not depend on 'gamma'"},
                 false);
}

TEST_F(NoiseCli, TheHelpNamesTheKeyThatLinksAColumn) {
  const auto h = cli("noise --help", "2>/dev/null");
  EXPECT_EQ(h.code, 0);
  EXPECT_NE(h.text.find("noise_param"), std::string::npos) << h.text;
  EXPECT_NE(h.text.find("--data"), std::string::npos) << h.text;
}

}  // namespace
}  // namespace kfw::model_world_noise_cli
