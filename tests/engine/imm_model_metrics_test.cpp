// Issue 28: a model file's named metrics (`model.metrics`): a statistic of a derived series or a
// grid axis's series from a time on, declared once and listed with the other metrics.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "model/model_result.h"
#include "model/model_scenario.h"

namespace kfw {
namespace {

using nlohmann::json;

json met_list(std::initializer_list<nlohmann::detail::json_ref<json>> e) {
  return json::array(e);
}

json met_param(double v, double lo, double hi) {
  return {{"value", v}, {"min", lo}, {"max", hi}, {"scale", "linear"}};
}

json met_preset() {
  json p = {{"format", "kfw-preset"}, {"version", 1}, {"scenario", "model"}};
  p["parameters"] = {{"q", met_param(0.3, 1e-4, 100)},
                     {"r", met_param(0.5, 1e-4, 100)},
                     {"t0", met_param(5.0, 0, 100)},
                     {"sim.dt", met_param(0.5, 0.01, 10)},
                     {"sim.duration", met_param(30, 1, 1000)}};
  p["model"] = {
      {"version", 2},
      {"states", met_list({"x", "v"})},
      {"x0", met_list({"0", "0"})},
      {"P0", met_list({"4", "1"})},
      {"process",
       {{"F", met_list({met_list({"1", "dt"}), met_list({"0", "1"})})},
        {"Q", met_list({met_list({"dt^3/3*q", "dt^2/2*q"}), met_list({"dt^2/2*q", "dt*q"})})}}},
      {"measurements",
       {{"pos",
         {{"roles", met_list({"z"})},
          {"H", met_list({met_list({"1", "0"})})},
          {"R", met_list({"r^2"})}}}}},
      {"truth", {{"x", "x_true"}}},
      {"derived", {{"err", {{"expression", "x - x_true"}, {"unit", "m"}}}}},
      {"metrics",
       {{"err_rms_late",
         {{"of", "derived.err"},
          {"stat", "rms"},
          {"from", "t0"},
          {"label", "late error"},
          {"unit", "m"},
          {"direction", "lower"}}},
        {"err_final", {{"of", "derived.err"}, {"stat", "final"}}},
        {"err_max", {{"of", "derived.err"}, {"stat", "max_abs"}}}}}};
  return p;
}

std::string met_error(const json& preset) {
  auto s = make_model_scenario(preset, "m.json");
  return s.ok() ? std::string() : s.error();
}

TEST(ImmModelMetrics, StatisticsOfASeriesFromATime) {
  auto s = make_model_scenario(met_preset(), "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto run = (*s)->run(*d, v);
  ASSERT_TRUE(run.ok()) << run.error();
  const auto& r = dynamic_cast<const model::ModelResult&>(**run);
  const std::vector<double>& err = r.derived.at(0);
  double sum = 0.0, top = 0.0, last = 0.0;
  int n = 0;
  for (std::size_t k = 0; k < err.size(); ++k) {
    top = std::max(top, std::fabs(err[k]));
    last = err[k];
    if (r.t[k] < 5.0) continue;
    sum += err[k] * err[k];
    ++n;
  }
  ASSERT_GT(n, 10);
  EXPECT_NEAR(r.metrics.at("err_rms_late"), std::sqrt(sum / n), 1e-12);
  EXPECT_NEAR(r.metrics.at("err_max"), top, 1e-12);
  EXPECT_DOUBLE_EQ(r.metrics.at("err_final"), last);
  EXPECT_DOUBLE_EQ(r.metrics.at("err_max"), r.metrics.at("derived.err.max"));
  // Declared once: the metrics table lists it with its label, unit and direction.
  bool listed = false;
  for (const auto& m : (*s)->metric_specs()) {
    if (m.key != "err_rms_late") continue;
    listed = m.label == "late error" && m.unit == "m" && m.direction == Direction::kLower;
  }
  EXPECT_TRUE(listed);
  // A window past the data: undefined, with the reason.
  ParamValues late = v;
  late["t0"] = 99.0;
  auto run2 = (*s)->run(*d, late);
  ASSERT_TRUE(run2.ok());
  EXPECT_EQ((*run2)->metrics.count("err_rms_late"), 0u);
  ASSERT_EQ((*run2)->undefined.count("err_rms_late"), 1u);
  // Not "no finite value": nothing was wrong with the series, the run was shorter.
  EXPECT_EQ((*run2)->undefined.at("err_rms_late"), "the run ends before t = 99 s");
}

TEST(ImmModelMetrics, MisusesAreRefusedWithTheKey) {
  const auto expect_error = [](const json& p, const std::string& key, const std::string& what) {
    const std::string e = met_error(p);
    EXPECT_NE(e.find(key), std::string::npos) << e;
    EXPECT_NE(e.find(what), std::string::npos) << e;
  };
  json p = met_preset();
  p["model"]["metrics"]["err_max"]["of"] = "derived.eror";
  expect_error(p, "model.metrics.err_max.of", "did you mean 'derived.err'");
  p = met_preset();
  p["model"]["metrics"]["err_max"]["stat"] = "median";
  expect_error(p, "model.metrics.err_max.stat", "statistic");
  p = met_preset();
  p["model"]["metrics"]["nis_mean"] = {{"of", "derived.err"}, {"stat", "rms"}};
  expect_error(p, "model.metrics.nis_mean", "kfw reports itself");
  p = met_preset();
  p["model"]["metrics"]["err_max"]["from"] = "x";
  expect_error(p, "model.metrics.err_max.from", "parameters only");
  p = met_preset();
  p["model"]["metrics"]["err_max"]["direction"] = "up";
  expect_error(p, "model.metrics.err_max.direction", "lower, higher or none");
  p = met_preset();
  p["model"]["metrics"][std::string(101, 'm')] = {{"of", "derived.err"}, {"stat", "rms"}};
  expect_error(p, "model.metrics.mmm", "at most 100 characters");
  p = met_preset();
  p["model"]["version"] = 1;
  p["model"].erase("derived");
  expect_error(p, "model.metrics", "version-2");
}

}  // namespace
}  // namespace kfw
