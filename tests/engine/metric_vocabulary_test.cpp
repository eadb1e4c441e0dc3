// Metrics declared once (metrics.h, issue 11): every metric a preset's run reports is declared,
// finite and labelled; the shared keys are always there or said to be undefined, with a reason;
// the JSON holds no null and no NaN. Without truth, rmse and nees_mean are undefined, not NaN.
#include "core/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "document/preset.h"
#include "document/workspace.h"

namespace kfw {
namespace {

// The keys every scenario reports or explains.
const char* const kShared[] = {"rmse", "nis_mean", "nis_in_bounds", "whiteness_p", "nees_mean"};

// What holds for any run: declared, finite, labelled keys; reasons for the undefined ones.
void expect_well_formed(const Scenario& s, const RunResult& r, const std::string& what) {
  for (const auto& [key, value] : r.metrics) {
    EXPECT_TRUE(is_declared_metric(s, key)) << what << ": '" << key << "' is not declared";
    EXPECT_TRUE(std::isfinite(value)) << what << ": " << key << " = " << value;
    EXPECT_FALSE(describe_metric(s, key, &r).label.empty()) << what << ": " << key;
    EXPECT_EQ(r.undefined.count(key), 0U) << what << ": " << key << " is defined and undefined";
  }
  for (const auto& [key, why] : r.undefined) {
    EXPECT_TRUE(is_declared_metric(s, key)) << what << ": undefined '" << key << "' not declared";
    EXPECT_FALSE(why.empty()) << what << ": " << key << " is undefined without a reason";
    EXPECT_FALSE(describe_metric(s, key, &r).label.empty()) << what << ": " << key;
  }
  for (const char* key : kShared) {
    EXPECT_TRUE(r.metrics.count(key) || r.undefined.count(key))
        << what << ": " << key << " is neither reported nor undefined";
  }
  const std::string text = metrics_to_json(r.metrics, r.undefined);
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  EXPECT_EQ(lower.find("null"), std::string::npos) << what << ": " << text;
  const auto j = nlohmann::json::parse(text);
  for (const auto& [key, value] : j.items()) {
    if (key == "undefined") {
      for (const auto& [k, why] : value.items())
        EXPECT_TRUE(why.is_string() && !why.get<std::string>().empty()) << what << ": " << k;
      continue;
    }
    ASSERT_TRUE(value.is_number()) << what << ": " << key << " = " << value;
    EXPECT_TRUE(std::isfinite(value.get<double>())) << what << ": " << key;
  }
  // NaN or infinity would have to appear as a bare token; keys and reasons are strings.
  for (const char* token : {": nan", ": -nan", ": inf", ": -inf"})
    EXPECT_EQ(lower.find(token), std::string::npos) << what << ": " << text;
}

std::vector<std::string> preset_names() {
  std::vector<std::string> names;
  for (const auto& e :
       std::filesystem::directory_iterator(std::string(KFW_SOURCE_DIR) + "/presets"))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

class EveryPreset : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryPreset, MetricsAreDeclaredFiniteAndExplained) {
  const std::string path = std::string(KFW_SOURCE_DIR) + "/presets/" + GetParam() + ".json";
  auto ws = open_workspace(path, {}, {});
  ASSERT_TRUE(ws.ok()) << ws.error();
  if (ws->data_path && !std::filesystem::exists(*ws->data_path))
    GTEST_SKIP() << "shared data not present: " << *ws->data_path;  // broad_imu, see README
  auto d = load_dataset(*ws);
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = ws->scenario->run(*d, ws->values);
  ASSERT_TRUE(r.ok()) << r.error();
  expect_well_formed(*ws->scenario, **r, GetParam());
  // Every preset's data carry truth (README, Tuning and consistency).
  EXPECT_TRUE((*r)->metrics.count("rmse")) << GetParam();
  EXPECT_TRUE((*r)->metrics.count("nees_mean")) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Presets, EveryPreset, ::testing::ValuesIn(preset_names()),
                         [](const auto& p) { return p.param; });

// A simulated dataset with its truth columns dropped, as a real log would come.
struct NoTruth {
  std::string scenario;                             // the seed preset (presets/NAME.json)
  std::vector<std::string> truth;                   // the columns dropped
  std::vector<std::pair<std::string, double>> set;  // parameters changed from the defaults
};

class WithoutTruth : public ::testing::TestWithParam<NoTruth> {};

TEST_P(WithoutTruth, RmseAndNeesAreUndefinedWithAReason) {
  const NoTruth& c = GetParam();
  auto p = load_preset(std::string(KFW_SOURCE_DIR) + "/presets/" + c.scenario + ".json");
  ASSERT_TRUE(p.ok()) << p.error();
  const Scenario* s = p->instance.get();
  auto v = p->values;
  for (const auto& [key, value] : c.set)
    v[key] = value;
  auto d = s->simulate(v);
  ASSERT_TRUE(d.ok()) << d.error();
  for (const auto& name : c.truth) {
    const int i = d->index(name);
    ASSERT_GE(i, 0) << name << " is not a column of the simulated " << c.scenario << " data";
    d->names.erase(d->names.begin() + i);
    d->columns.erase(d->columns.begin() + i);
  }
  auto r = s->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  expect_well_formed(*s, **r, c.scenario + " without truth");
  for (const char* key : {"rmse", "nees_mean"}) {
    EXPECT_EQ((*r)->metrics.count(key), 0U) << c.scenario << ": " << key;
    ASSERT_TRUE((*r)->undefined.count(key)) << c.scenario << ": " << key;
    EXPECT_FALSE((*r)->undefined.at(key).empty()) << c.scenario << ": " << key;
  }
  // The innovations need no truth.
  EXPECT_TRUE((*r)->metrics.count("nis_mean")) << c.scenario;
}

INSTANTIATE_TEST_SUITE_P(
    Scenarios, WithoutTruth,
    ::testing::Values(NoTruth{"helicopter", {"truth", "bias_truth"}, {}},
                      NoTruth{"ballbeam", {"truth", "v_truth"}, {{"mode", 1.0}}},  // replay
                      NoTruth{"radome",
                              {"x_m", "y_m", "z_m", "R_psi_true", "R_theta_true", "psi_los_rad",
                               "theta_los_rad"},
                              {}},
                      NoTruth{"underwater", {"x_true", "y_true", "z_true", "psi_true"}, {}}),
    [](const auto& p) { return p.param.scenario; });

// The shared vocabulary itself: patterns resolve, every spec has a label and a description.
TEST(MetricVocabulary, SharedSpecsAreComplete) {
  for (const auto& spec : shared_metric_specs()) {
    EXPECT_FALSE(spec.label.empty()) << spec.key;
    EXPECT_FALSE(spec.description.empty()) << spec.key;
  }
  for (const auto& name : preset_names()) {
    auto p = load_preset(std::string(KFW_SOURCE_DIR) + "/presets/" + name + ".json");
    ASSERT_TRUE(p.ok()) << p.error();
    const Scenario* s = p->instance.get();
    for (const auto& spec : s->metric_specs()) {
      EXPECT_FALSE(spec.label.empty()) << name << ": " << spec.key;
      EXPECT_FALSE(spec.description.empty()) << name << ": " << spec.key;
      EXPECT_TRUE(is_declared_metric(*s, spec.key)) << name << ": " << spec.key;
    }
    EXPECT_TRUE(is_declared_metric(*s, "whiteness_p.anything")) << name;
    EXPECT_FALSE(is_declared_metric(*s, "no_such_metric")) << name;
  }
}

}  // namespace
}  // namespace kfw
