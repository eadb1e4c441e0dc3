// The bad-input matrix, model files (issue 16): `kfw-cli run MODEL.json --out --metrics` on the
// shipped cv1d model with one thing broken. Exit 2 before any work for a bad file (one line naming
// the file and the dotted key, with the position in an expression), exit 1 with step and time for
// a run that breaks down; nothing written either way (common/bad_input.h).
#include <nlohmann/json.hpp>

#include "common/bad_input.h"

namespace kfw {
namespace {

using Json = nlohmann::ordered_json;

class BadModel : public testing::BadInput {
 protected:
  // cv1d.json with one edit applied to its JSON.
  std::string model(const std::string& name, const std::function<void(Json&)>& edit) {
    Json j = Json::parse(source("presets/models/cv1d.json"));
    edit(j);
    return file(name, j.dump(2));
  }
  void refused(const std::string& name, const std::function<void(Json&)>& edit,
               std::initializer_list<std::string> fragments, int code = 2) {
    SCOPED_TRACE(name);
    auto r = expect_refused("run " + model(name, edit), code, fragments);
    if (code == 2) {
      EXPECT_NE(r.text.find(name), std::string::npos) << r.text;
    }
  }
};

TEST_F(BadModel, ExpressionsThatDoNotParse) {
  refused("syntax.json",
          [](Json& j) { j["model"]["measurements"]["position"]["R"][0] = "sigma_r^"; },
          {"model.measurements.position.R[0]", "position"});
  refused("unknown.json", [](Json& j) { j["model"]["process"]["F"][0][1] = "dtt"; },
          {"model.process.F[0][1]", "unknown symbol 'dtt'"});
  refused("func.json", [](Json& j) { j["model"]["process"]["F"][0][1] = "ln(dt)"; },
          {"model.process.F[0][1]", "unknown function 'ln'"});
  refused("empty.json", [](Json& j) { j["model"]["process"]["F"][0][1] = ""; },
          {"model.process.F[0][1]", "empty expression"});
  refused("long.json",
          [](Json& j) { j["model"]["process"]["F"][0][1] = std::string(50000, '(') + "dt"; },
          {"model.process.F[0][1]"});
  refused("number.json", [](Json& j) { j["model"]["process"]["F"][0][1] = "1e999"; },
          {"model.process.F[0][1]"});
}

TEST_F(BadModel, ShapesTypesAndKeys) {
  refused("shape.json", [](Json& j) { j["model"]["process"]["F"][0] = Json::array({"1"}); },
          {"model.process.F"});
  refused("type.json", [](Json& j) { j["model"]["process"]["F"][0][0] = true; },
          {"model.process.F[0][0]"});
  refused("states.json", [](Json& j) { j["model"]["states"] = "x"; }, {"model.states"});
  refused("key.json", [](Json& j) { j["model"]["filtr"] = "kf"; }, {"model.filtr"});
  refused("version.json", [](Json& j) { j["model"]["version"] = 4294967297.0; }, {"model.version"});
  refused("filter.json", [](Json& j) { j["model"]["filter"] = "pf"; }, {"model.filter"});
  refused("nomodel.json", [](Json& j) { j.erase("model"); }, {"model"});
}

TEST_F(BadModel, CovariancesThatAreNotPositive) {
  // P0 from constants: non-PSD is a file error, found before the run.
  refused("p0.json",
          [](Json& j) {
            j["model"]["P0"] = Json::array({Json::array({"1", "2"}), Json::array({"2", "1"})});
          },
          {"model.P0"});
  refused("p0_neg.json",
          [](Json& j) {
            j["model"]["P0"] = Json::array({"-1", "1"});
          },
          {"model.P0"});
  refused("p0_asym.json",
          [](Json& j) {
            j["model"]["P0"] = Json::array({Json::array({"1", "0.5"}), Json::array({"0", "1"})});
          },
          {"model.P0"});
  // A parameter-only R that is negative: refused before the run (exit 2), named.
  refused("r_neg.json",
          [](Json& j) { j["model"]["measurements"]["position"]["R"][0] = "-sigma_r^2"; },
          {"model.measurements.position.R"});
  // A Q of dt: checked at sim.dt when the file loads (issue 27), refused before the run.
  refused("q_neg.json", [](Json& j) { j["model"]["process"]["Q"][1][1] = "-dt^2*sigma_a^2"; },
          {"model.process.Q", "at dt = 0.1 s (sim.dt)"});
}

TEST_F(BadModel, ParametersOutOfTheirRange) {
  refused("val.json", [](Json& j) { j["parameters"]["sigma_a"]["value"] = 1e9; },
          {"parameters.sigma_a: ", "out of range"});
  refused("nan.json", [](Json& j) { j["parameters"]["sigma_a"]["value"] = "nan"; },
          {"parameters.sigma_a.value"});
}

}  // namespace
}  // namespace kfw
