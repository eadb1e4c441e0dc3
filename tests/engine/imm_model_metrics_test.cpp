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

// model.metrics_from: the standard accuracy and consistency metrics count the rows from that time
// (seed 001's t ≥ 10 s); a run that ends before says so; a version-1 file cannot carry the key.
TEST(ImmModelMetrics, MetricsFromStartsTheStandardMetrics) {
  json p = met_preset();
  p["model"]["metrics_from"] = "t0";
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  auto run = (*s)->run(*d, v);
  ASSERT_TRUE(run.ok()) << run.error();
  const auto& r = dynamic_cast<const model::ModelResult&>(**run);
  double se = 0.0, nis = 0.0, nees = 0.0;
  int n = 0, updates = 0;
  const auto channels = r.channels();
  const auto ne = r.nees_series();
  for (std::size_t k = 0; k < r.steps(); ++k) {
    if (r.t[k] < 5.0) continue;
    const double e = r.x[0][k] - r.truth[0][k];
    se += e * e;
    nees += ne.nees[k];
    ++n;
    if (std::isfinite(channels[0].nis[k])) {
      nis += channels[0].nis[k];
      ++updates;
    }
  }
  ASSERT_GT(n, 10);
  EXPECT_NEAR(r.metrics.at("rmse.x"), std::sqrt(se / n), 1e-12);
  EXPECT_DOUBLE_EQ(r.metrics.at("rmse"), r.metrics.at("rmse.x"));
  EXPECT_NEAR(r.metrics.at("nis_mean"), nis / updates, 1e-12);
  EXPECT_NEAR(r.metrics.at("nees_mean"), nees / n / ne.dof, 1e-12);
  // The same run without the key counts every row: a different number.
  auto whole = make_model_scenario(met_preset(), "m.json");
  ASSERT_TRUE(whole.ok());
  auto all = (*whole)->run(*d, v);
  ASSERT_TRUE(all.ok());
  EXPECT_GT(std::fabs((*all)->metrics.at("rmse.x") - r.metrics.at("rmse.x")), 1e-6);
  // Past the end: undefined, with the reason and the key.
  ParamValues late = v;
  late["t0"] = 99.0;
  auto none = (*s)->run(*d, late);
  ASSERT_TRUE(none.ok()) << none.error();
  for (const char* k : {"rmse", "rmse.x", "rmse.v", "nis_mean", "nees_mean", "nll"}) {
    EXPECT_EQ((*none)->metrics.count(k), 0u) << k;
    ASSERT_EQ((*none)->undefined.count(k), 1u) << k;
    EXPECT_EQ((*none)->undefined.at(k), "the run ends before t = 99 s (model.metrics_from)") << k;
  }
  json p1 = met_preset();
  p1["model"]["version"] = 1;
  p1["model"].erase("metrics");
  p1["model"].erase("derived");
  p1["model"]["metrics_from"] = "1";
  EXPECT_EQ(met_error(p1), "m.json: model.metrics_from: a version-2 key: set \"version\": 2");
  p["model"]["metrics_from"] = "x";
  EXPECT_NE(met_error(p).find("model.metrics_from"), std::string::npos) << met_error(p);
}

// Named metrics are listed in the file's order (the metrics table, tune, sweep), not sorted.
TEST(ImmModelMetrics, ListedInTheFilesOrder) {
  nlohmann::ordered_json p = nlohmann::ordered_json::parse(met_preset().dump());
  p["model"]["metrics"] = nlohmann::ordered_json::parse(
      R"({"z_last": {"of": "derived.err", "stat": "final"},
          "a_max": {"of": "derived.err", "stat": "max_abs"}})");
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  std::vector<std::string> keys;
  for (const auto& m : (*s)->metric_specs()) {
    if (m.key == "z_last" || m.key == "a_max") keys.push_back(m.key);
  }
  EXPECT_EQ(keys, (std::vector<std::string>{"z_last", "a_max"}));
}

}  // namespace
}  // namespace kfw
