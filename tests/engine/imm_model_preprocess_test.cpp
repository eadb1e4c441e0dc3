// Issue 28: pre-processed measurements (a channel's `z`) and x0 from a channel's first sample —
// the filter compares the components, starts at the channel's first sample without applying it
// again, and every misuse is refused with the file and key named.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/dataset.h"
#include "core/scenario.h"
#include "model/model_result.h"
#include "model/model_scenario.h"

namespace kfw {
namespace {

using nlohmann::json;

json pre_list(std::initializer_list<nlohmann::detail::json_ref<json>> e) {
  return json::array(e);
}

json pre_param(double v, double lo, double hi) {
  return {{"value", v}, {"min", lo}, {"max", hi}, {"scale", "linear"}};
}

// A constant-velocity filter whose sensor reports the position in cm with an offset: `z` undoes
// both; x0 takes the position from the first sample.
json pre_preset() {
  json p = {{"format", "kfw-preset"}, {"version", 1}, {"scenario", "model"}};
  p["parameters"] = {
      {"q", pre_param(0.3, 1e-4, 100)},     {"r", pre_param(0.5, 1e-4, 100)},
      {"offset", pre_param(2.0, -10, 10)},  {"p0", pre_param(0.0, -1e6, 1e6)},
      {"sim.dt", pre_param(0.5, 0.01, 10)}, {"sim.duration", pre_param(30, 1, 1000)}};
  p["model"] = {
      {"version", 2},
      {"states", pre_list({"x", "v"})},
      {"expressions", {{"metres", "cm/100 - offset"}}},
      {"x0", pre_list({{{"first", "pos.p"}}, "0"})},
      {"P0", pre_list({"4", "1"})},
      {"process",
       {{"F", pre_list({pre_list({"1", "dt"}), pre_list({"0", "1"})})},
        {"Q", pre_list({pre_list({"dt^3/3*q", "dt^2/2*q"}), pre_list({"dt^2/2*q", "dt*q"})})}}},
      {"measurements",
       {{"pos",
         {{"roles", pre_list({"cm"})},
          {"z", pre_list({{{"name", "p"}, {"unit", "m"}, {"expression", "metres"}}})},
          {"H", pre_list({pre_list({"1", "0"})})},
          {"R", pre_list({"r^2 + 0*cm"})}}}}},
      {"truth", {{"x", "x_true"}}}};
  return p;
}

// Rows 0..n−1 at 0.5 s: position 0.3 t + 0.01 t², the sensor's cm with the offset, missing
// before `first`.
Dataset pre_data(std::size_t n, std::size_t first, double offset) {
  Dataset d;
  d.add("t", n);
  d.add("cm", n);
  d.add("x_true", n);
  for (std::size_t k = 0; k < n; ++k) {
    const double t = 0.5 * static_cast<double>(k);
    const double x = 0.3 * t + 0.01 * t * t + 0.05 * std::sin(3.0 * t);
    d.columns[0][k] = t;
    d.columns[1][k] = k < first ? std::numeric_limits<double>::quiet_NaN() : (x + offset) * 100.0;
    d.columns[2][k] = 0.3 * t + 0.01 * t * t;
  }
  return d;
}

std::string pre_error(const json& preset) {
  auto s = make_model_scenario(preset, "m.json");
  return s.ok() ? std::string() : s.error();
}

TEST(ImmModelPreprocess, StartsAtTheFirstSampleAndEqualsTheConvertedLog) {
  auto s = make_model_scenario(pre_preset(), "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const ParamValues v = (*s)->params().defaults();
  const std::size_t first = 3, n = 40;
  const Dataset d = pre_data(n, first, 2.0);
  auto run = (*s)->run(d, v);
  ASSERT_TRUE(run.ok()) << run.error();
  const auto& r = dynamic_cast<const model::ModelResult&>(**run);

  // The same filter on the converted log from the first sample on, x0 = that sample (a
  // parameter), its first sample not applied (blanked): the plain model file's semantics.
  json plain = pre_preset();
  auto& m = plain["model"];
  m["x0"] = pre_list({"p0", "0"});
  m["measurements"]["pos"].erase("z");
  m["measurements"]["pos"]["roles"] = pre_list({"p"});
  m["measurements"]["pos"]["R"] = pre_list({"r^2"});
  m.erase("expressions");
  auto s2 = make_model_scenario(plain, "plain.json");
  ASSERT_TRUE(s2.ok()) << s2.error();
  Dataset d2;
  d2.add("t", n - first);
  d2.add("p", n - first);
  d2.add("x_true", n - first);
  for (std::size_t k = first; k < n; ++k) {
    d2.columns[0][k - first] = d.columns[0][k];
    d2.columns[1][k - first] = d.columns[1][k] / 100.0 - 2.0;
    d2.columns[2][k - first] = d.columns[2][k];
  }
  ParamValues v2 = v;
  v2["p0"] = d2.columns[1][0];
  d2.columns[1][0] = std::numeric_limits<double>::quiet_NaN();
  auto run2 = (*s2)->run(d2, v2);
  ASSERT_TRUE(run2.ok()) << run2.error();
  const auto& r2 = dynamic_cast<const model::ModelResult&>(**run2);

  for (std::size_t k = 0; k < first; ++k)
    EXPECT_TRUE(std::isnan(r.x[0][k])) << "no estimate before the first sample, row " << k;
  EXPECT_TRUE(std::isnan(r.chans[0].nis[first])) << "the first sample made x0";
  for (std::size_t k = first; k < n; ++k) {
    for (std::size_t i = 0; i < 2; ++i) {
      const double b = r2.x[i][k - first], sd = std::sqrt(r2.P[r2.diag[i]][k - first]);
      EXPECT_NEAR(r.x[i][k], b, 1e-12 * (std::fabs(b) + sd)) << "row " << k;
    }
    if (k > first) {
      EXPECT_NEAR(r.z[0][k], d2.columns[1][k - first], 1e-12) << "row " << k;
    }
  }
  EXPECT_EQ(r.chans[0].updates, n - first - 1);
  EXPECT_EQ(r.chans[0].roles.at(0), "p");  // the component names the channel's series
  EXPECT_EQ(r.role_names.at(0), "p");
}

TEST(ImmModelPreprocess, ANonFiniteComponentSkipsTheUpdate) {
  json p = pre_preset();
  p["model"]["measurements"]["pos"]["z"][0]["expression"] = "sqrt(cm - 1500)";  // NaN below 15 m
  p["model"]["x0"] = pre_list({"0", "0"});
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  Dataset d = pre_data(40, 0, 10.0);
  d.columns[1][0] = 2000.0;  // the first due update applies
  d.columns[1][20] = 100.0;  // then one component is NaN
  auto run = (*s)->run(d, (*s)->params().defaults());
  ASSERT_TRUE(run.ok()) << run.error();
  const auto& r = dynamic_cast<const model::ModelResult&>(**run);
  EXPECT_GE(r.chans[0].skipped, 1u);
  bool named = false;
  for (const auto& w : r.warnings)
    named = named || w.find("model.measurements.pos.z[0]") != std::string::npos;
  EXPECT_TRUE(named);
}

TEST(ImmModelPreprocess, MisusesAreRefusedWithTheKey) {
  const auto expect_error = [](json p, const std::string& key) {
    const std::string e = pre_error(p);
    EXPECT_NE(e.find(key), std::string::npos) << e;
    EXPECT_NE(e.find("m.json"), std::string::npos) << e;
  };
  {
    json p = pre_preset();  // a state in z
    p["model"]["measurements"]["pos"]["z"][0]["expression"] = "x + cm";
    expect_error(p, "model.measurements.pos.z[0].expression");
  }
  {
    json p = pre_preset();  // version 1
    p["model"]["version"] = 1;
    p["model"].erase("expressions");
    p["model"]["measurements"]["pos"]["z"][0]["expression"] = "cm/100";
    expect_error(p, "model.measurements.pos.z");
  }
  {
    json p = pre_preset();  // another channel's column
    p["model"]["measurements"]["vel"] = {{"roles", pre_list({"vv"})},
                                         {"H", pre_list({pre_list({"0", "1"})})},
                                         {"R", pre_list({"1"})}};
    p["model"]["measurements"]["vel"]["z"] = pre_list({{{"name", "w"}, {"expression", "cm"}}});
    expect_error(p, "model.measurements.vel.z[0].expression");
  }
  {
    json p = pre_preset();  // an unknown component
    p["model"]["x0"][0]["first"] = "pos.q";
    expect_error(p, "model.x0[0].first");
  }
  {
    json p = pre_preset();  // noise_param
    p["model"]["measurements"]["pos"]["noise_param"] = "r";
    expect_error(p, "model.measurements.pos.noise_param");
  }
  {
    json p = pre_preset();  // a role that is not a name
    p["model"]["measurements"]["pos"]["roles"] = pre_list({"c m"});
    expect_error(p, "model.measurements.pos.roles[0]");
  }
}

TEST(ImmModelPreprocess, DerivedQuantitiesReadTheComponentsAndTheColumns) {
  json p = pre_preset();
  p["model"]["derived"] = {{"err", "p - x_true"}, {"raw", "cm/100 - offset - x_true"}};
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  auto run = (*s)->run(pre_data(40, 0, 2.0), (*s)->params().defaults());
  ASSERT_TRUE(run.ok()) << run.error();
  const auto& r = dynamic_cast<const model::ModelResult&>(**run);
  ASSERT_EQ(r.derived.size(), 2u);
  EXPECT_TRUE(std::isnan(r.derived[0][0]));  // the first sample made x0: no component compared
  EXPECT_NEAR(r.derived[0][5], r.z[0][5] - r.truth[0][5], 1e-12);
  // The channel's column as read, at every row (the first included).
  EXPECT_NEAR(r.derived[1][0], 0.0, 1e-12);  // x = x_true at t = 0
  EXPECT_NEAR(r.derived[1][5], r.derived[0][5], 1e-12);
}

TEST(ImmModelPreprocess, AModelWithZSimulatesOnlyThroughAWorld) {
  auto s = make_model_scenario(pre_preset(), "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  auto d = (*s)->simulate((*s)->params().defaults());
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().find("declare a world"), std::string::npos) << d.error();
}

}  // namespace
}  // namespace kfw
