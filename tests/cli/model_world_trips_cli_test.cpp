// Issue 27, model files part 2 — the newcomer trips as `kfw-cli` shows them, in the order of the
// engine's sections (tests/engine/model_world_trips_test.cpp): exit codes, messages and listings.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/bad_input.h"

namespace kfw {
namespace {

using Json = nlohmann::ordered_json;

class ModelTripsCli : public testing::BadInput {
 protected:
  // presets/models/NAME.json with one edit applied to its JSON, written as FILE.
  std::string model(const std::string& file_name, const std::function<void(Json&)>& edit,
                    const std::string& name = "cv1d") {
    Json j = Json::parse(source("presets/models/" + name + ".json"));
    edit(j);
    return file(file_name, j.dump(2));
  }
};

// ---- 1. A dimension message names the short row

TEST_F(ModelTripsCli, AShortRowIsNamed) {
  const auto f = model("short.json", [](Json& j) { j["model"]["process"]["F"][1] = {"1"}; });
  expect_refused("run " + f, 2,
                 {"short.json: model.process.F: wrong dimensions: expected 2×2, "
                  "model.process.F[1] has 1 entry"});
}

// ---- 2. "Did you mean"

TEST_F(ModelTripsCli, AMisspeltKeySuggestsTheNearest) {
  const auto f = model("key.json", [](Json& j) {
    j["model"]["mesurements"] = j["model"]["measurements"];
    j["model"].erase("measurements");
  });
  expect_refused("run " + f, 2,
                 {"key.json: model.mesurements: unknown key (did you mean 'measurements'?)"});
  const auto g = model("sym.json", [](Json& j) { j["model"]["process"]["F"][0][1] = "dtt"; });
  expect_refused("run " + g, 2,
                 {"sym.json: model.process.F[0][1]: unknown symbol 'dtt'", "(did you mean 'dt'?)"});
}

// ---- 3. A Q that depends on dt: exit 2

TEST_F(ModelTripsCli, ADtDependentQNotPsdAtSimDtIsRefusedBeforeAnyWork) {
  const auto f =
      model("q.json", [](Json& j) { j["model"]["process"]["Q"][1][1] = "-dt^2*sigma_a^2"; });
  expect_refused("run " + f, 2,
                 {"q.json: model.process.Q: not positive semidefinite at dt = 0.1 s (sim.dt)"});
  expect_refused("simulate " + f + " --out " + out, 2, {"q.json", "model.process.Q"}, false);
}

TEST_F(ModelTripsCli, ADtDependentQNotPsdAtAnIntervalOfTheDataIsRefusedBeforeTheRun) {
  // PSD for dt ≥ 0.05 s or so: the preset's 0.1 s passes, the data's 0.02 s does not.
  const auto f = model("qdt.json", [](Json& j) {
    j["model"]["process"]["Q"][1][1] = "dt^2*sigma_a^2 + 0.1*(dt - 0.05)";
  });
  std::ostringstream csv;
  csv << "t,z\n";
  double t = 0.0;
  for (int k = 0; k < 30; ++k) {
    csv << t << "," << 0.1 * k << "\n";
    t += k == 11 ? 0.02 : 0.1;
  }
  const auto data = file("log.csv", csv.str());
  expect_refused("run " + f + " --data " + data, 2,
                 {"qdt.json: model.process.Q: not positive semidefinite at dt = 0.02 s",
                  "the interval into step 12 of", "log.csv"});
}

// ---- 4. An update that cannot happen: exit 1

TEST_F(ModelTripsCli, AnUpdateThatCannotHappenAtTheFirstDueUpdateFailsTheRun) {
  const auto f = model("s.json", [](Json& j) {
    j["model"]["measurements"]["position"]["H"] = Json::parse(R"([["0", "0"]])");
    j["model"]["measurements"]["position"]["R"] = {"0"};
  });
  for (const char* filter : {"kf", "ukf"}) {
    SCOPED_TRACE(filter);
    expect_refused("run " + f + " --set filter=" + filter, 1,
                   {"step 0 (t = 0 s): channel 'position': its first due update cannot be applied",
                    "model.measurements.position.H", "model.measurements.position.R"});
  }
}

// ---- 5. Parameters in the file's order

TEST_F(ModelTripsCli, ParamsAreListedInTheFilesOrder) {
  for (const char* name : {"cv1d", "pendulum", "helicopter_indirect"}) {
    SCOPED_TRACE(name);
    const std::string path = std::string(KFW_SOURCE_DIR) + "/presets/models/" + name + ".json";
    const auto c = testing::cli("params " + path, "2>/dev/null");
    ASSERT_EQ(c.code, 0) << c.text;
    std::vector<std::string> listed;
    std::istringstream lines(c.text);
    for (std::string line; std::getline(lines, line);)
      listed.push_back(line.substr(0, line.find('\t')));
    std::vector<std::string> declared;
    const Json j = Json::parse(source("presets/models/" + std::string(name) + ".json"));
    for (const auto& [key, value] : j.at("parameters").items())
      declared.push_back(key);
    ASSERT_GE(listed.size(), declared.size());
    listed.resize(declared.size());
    EXPECT_EQ(listed, declared);
  }
}

// ---- 6. A primary of several states

TEST_F(ModelTripsCli, APrimaryOfSeveralStatesGivesTheEuclideanRmse) {
  const auto f = model(
      "primary.json",
      [](Json& j) {
        j["model"]["version"] = 2;
        j["model"]["primary"] = {"px", "py"};
      },
      "cv2d");
  const auto c = testing::cli("run " + f + " --set sim.duration=20 --metrics " + metrics,
                              "2>/dev/null >/dev/null");
  ASSERT_EQ(c.code, 0) << c.text;
  const auto m = nlohmann::json::parse(read(metrics));
  const double px = m.at("rmse.px"), py = m.at("rmse.py"), rmse = m.at("rmse");
  EXPECT_NEAR(rmse, std::sqrt(px * px + py * py), 1e-9 * rmse);
  EXPECT_GT(rmse, std::max(px, py));
}

}  // namespace
}  // namespace kfw
