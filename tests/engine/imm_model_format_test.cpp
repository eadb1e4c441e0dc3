// Issue 28: the modes block of a model file — what loads (list, grid, gained parameters), what is
// refused with a message naming the file and key, and a grid re-run with new axes.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "core/scenario.h"
#include "model/imm/imm_spec.h"
#include "model/model_result.h"
#include "model/model_scenario.h"

namespace kfw {
namespace {

using nlohmann::json;

// A list (nlohmann reads {"a", "b"} as a key and its value).
json fmt_list(std::initializer_list<nlohmann::detail::json_ref<json>> e) {
  return json::array(e);
}

json fmt_param(double v, double lo, double hi, const char* scale = "linear") {
  return {{"value", v}, {"min", lo}, {"max", hi}, {"scale", scale}};
}

json imm_base_preset() {
  json p = {{"format", "kfw-preset"}, {"version", 1}, {"scenario", "model"}};
  p["parameters"] = {{"q", fmt_param(0.1, 1e-4, 100, "log")},
                     {"q_man", fmt_param(3.0, 1e-4, 100, "log")},
                     {"r", fmt_param(1.0, 1e-4, 100, "log")},
                     {"sim.dt", fmt_param(0.5, 0.01, 10)},
                     {"sim.duration", fmt_param(30, 1, 1000)}};
  p["model"] = {{"version", 2},
                {"states", fmt_list({"x", "v"})},
                {"x0", fmt_list({"0", "0"})},
                {"P0", fmt_list({"20", "4"})},
                {"process",
                 {{"F", fmt_list({fmt_list({"1", "dt"}), fmt_list({"0", "1"})})},
                  {"Q", fmt_list({fmt_list({"dt^4/4*q^2", "dt^3/2*q^2"}),
                                  fmt_list({"dt^3/2*q^2", "dt^2*q^2"})})}}},
                {"measurements",
                 {{"pos",
                   {{"roles", fmt_list({"z"})},
                    {"H", fmt_list({fmt_list({"1", "0"})})},
                    {"R", fmt_list({"r^2"})}}}}},
                {"truth", {{"x", "x_true"}}}};
  return p;
}

json imm_two_modes() {
  return {{"list", {{{"name", "quiet"}}, {{"name", "man"}, {"params", {{"q", "q_man"}}}}}}};
}

// The load error of `preset` (empty when it loads).
std::string imm_load_error(const json& preset) {
  auto s = make_model_scenario(preset, "m.json");
  return s.ok() ? std::string() : s.error();
}

std::string with_modes_error(const json& modes) {
  json p = imm_base_preset();
  p["model"]["modes"] = modes;
  return imm_load_error(p);
}

TEST(ImmModelFormat, AListLoadsAndGainsMarkovStay) {
  json p = imm_base_preset();
  p["model"]["modes"] = imm_two_modes();
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const ParamSpec* stay = (*s)->params().find("markov.stay");
  ASSERT_NE(stay, nullptr);
  EXPECT_DOUBLE_EQ(stay->def, 0.95);
  // An IMM has no steady-state gain.
  EXPECT_FALSE((*s)->gain((*s)->params().defaults()).ok());
  bool modes_metric = false;
  for (const auto& m : (*s)->metric_specs())
    modes_metric = modes_metric || m.key == "imm.modes";
  EXPECT_TRUE(modes_metric);
}

TEST(ImmModelFormat, RefusalsNameTheFileAndTheKey) {
  EXPECT_EQ(with_modes_error({{"list", {{{"name", "a"}}}}}),
            "m.json: model.modes.list: expected a list of two or more modes");
  EXPECT_EQ(with_modes_error({{"lst", json::array()}}),
            "m.json: model.modes.lst: unknown key (did you mean 'list'?)");
  EXPECT_EQ(with_modes_error({{"list", imm_two_modes()["list"]}, {"grid", json::array()}}),
            "m.json: model.modes: expected one of \"list\" (named modes) or \"grid\" (axes)");
  json bad = imm_two_modes();
  bad["list"][1]["params"] = {{"q_mann", 1.0}};
  EXPECT_NE(with_modes_error(bad).find("m.json: model.modes.list[1].params.q_mann: unknown "
                                       "parameter of the model 'q_mann' (did you mean 'q_man'?)"),
            std::string::npos)
      << with_modes_error(bad);
  bad = imm_two_modes();
  bad["list"][1]["params"] = {{"q", "nope"}};
  EXPECT_NE(with_modes_error(bad).find("m.json: model.modes.list[1].params.q: unknown parameter"),
            std::string::npos);
  bad = imm_two_modes();
  bad["list"][1]["name"] = "quiet";
  EXPECT_EQ(with_modes_error(bad), "m.json: model.modes.list[1].name: 'quiet' twice");
  bad = imm_two_modes();
  bad["list"][1]["process"] = {{"F", fmt_list({fmt_list({"1", "dt"}), fmt_list({"0"})})},
                               {"Q", fmt_list({"1", "1"})}};
  EXPECT_NE(with_modes_error(bad).find("m.json: model.modes.list[1].process.F: wrong dimensions"),
            std::string::npos)
      << with_modes_error(bad);
  bad = imm_two_modes();
  bad["list"][1]["measurements"] = {{"radar", {{"R", fmt_list({"1"})}}}};
  EXPECT_NE(with_modes_error(bad).find("m.json: model.modes.list[1].measurements.radar: unknown "
                                       "channel 'radar'"),
            std::string::npos)
      << with_modes_error(bad);
  bad = imm_two_modes();
  bad["markov"] = {{"matrix", {{0.9, 0.2}, {0.1, 0.9}}}};
  EXPECT_EQ(with_modes_error(bad), "m.json: model.modes.markov.matrix[0]: sums to 1.1, not 1");
  bad = imm_two_modes();
  bad["mu0"] = {1.0};
  EXPECT_EQ(with_modes_error(bad), "m.json: model.modes.mu0: expected \"uniform\" or 2 numbers");
  EXPECT_NE(with_modes_error({{"grid", {{{"param", "q"}, {"min", 0.1}, {"max", 1}}}}})
                .find("m.json: model.modes.grid[0]: missing key 'n'"),
            std::string::npos);
  EXPECT_NE(with_modes_error({{"grid", {{{"param", "q"}, {"min", 0.1}, {"max", 1000}, {"n", 3}}}}})
                .find("m.json: model.modes.grid[0].max: 1000 is outside the range [0.0001, 100] of "
                      "grid.q.max"),
            std::string::npos);
}

TEST(ImmModelFormat, VersionOneAndGatesAreRefused) {
  json p = imm_base_preset();
  p["model"]["version"] = 1;
  p["model"]["modes"] = imm_two_modes();
  EXPECT_EQ(imm_load_error(p), "m.json: model.modes: a version-2 key: set \"version\": 2");
  p = imm_base_preset();
  p["model"]["measurements"]["pos"]["gate"] = 0.99;
  p["model"]["modes"] = imm_two_modes();
  EXPECT_EQ(imm_load_error(p),
            "m.json: model.measurements.pos.gate: a gate cannot be combined with modes yet");
}

TEST(ImmModelFormat, WhatIsCheckedWhenTheFileLoads) {
  // Angle states: their μ-weighted mean would not wrap.
  json p = imm_base_preset();
  p["model"]["states"][0] = {{"name", "x"}, {"angle", "rad"}};
  p["model"]["modes"] = imm_two_modes();
  EXPECT_EQ(imm_load_error(p),
            "m.json: model.states: the angle state 'x' cannot be mixed across modes yet (its mean "
            "would not wrap)");
  // A declared kf that a mode's nonlinear process rules out.
  p = imm_base_preset();
  json modes = imm_two_modes();
  modes["list"][1]["process"] = {{"f", fmt_list({"x + dt*v", "v*cos(0.01*dt)"})},
                                 {"Q", fmt_list({fmt_list({"dt^4/4*q^2", "dt^3/2*q^2"}),
                                                 fmt_list({"dt^3/2*q^2", "dt^2*q^2"})})}};
  p["model"]["modes"] = modes;
  p["model"]["filter"] = "kf";
  EXPECT_EQ(imm_load_error(p),
            "m.json: model.filter: 'kf' is not a filter for this model (one of ekf ukf; a mode's "
            "process or h is not linear)");
  // A grid that is empty at the preset's values is refused at load, naming its keys.
  p = imm_base_preset();
  p["model"]["modes"] = {{"grid", {{{"param", "q"}, {"min", 3.0}, {"max", 2.0}, {"n", 3}}}}};
  EXPECT_EQ(imm_load_error(p), "m.json: grid.q.min (3) must not exceed grid.q.max (2)");
  // A mode whose R is not PSD at the preset's values: at load, naming the mode.
  p = imm_base_preset();
  modes = imm_two_modes();
  modes["list"][1]["measurements"] = {{"pos", {{"R", fmt_list({"-r^2"})}}}};
  p["model"]["modes"] = modes;
  EXPECT_NE(imm_load_error(p).find("(in mode 'man')"), std::string::npos) << imm_load_error(p);
}

TEST(ImmModelFormat, HugeInitialProbabilitiesNormalise) {
  // mu0 entries near the largest double: their sum overflowed, every μ became 0 (exit 1 with an
  // empty reason); they are normalised relative to the largest first.
  json p = imm_base_preset();
  json modes = imm_two_modes();
  modes["mu0"] = fmt_list({1e308, 1e308});
  p["model"]["modes"] = modes;
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok());
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_TRUE(std::isfinite(r->get()->metrics.at("rmse")));
}

TEST(ImmModelFormat, ANonlinearModeRulesOutTheKf) {
  json p = imm_base_preset();
  json modes = imm_two_modes();
  modes["list"][1]["process"] = {{"f", fmt_list({"x + dt*v", "v*cos(0.01*dt)"})},
                                 {"Q", fmt_list({fmt_list({"dt^4/4*q^2", "dt^3/2*q^2"}),
                                                 fmt_list({"dt^3/2*q^2", "dt^2*q^2"})})}};
  p["model"]["modes"] = modes;
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const ParamSpec* f = (*s)->params().find("filter");
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->choices, (std::vector<std::string>{"ekf", "ukf"}));
  ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok());
  for (double kind : {0.0, 1.0}) {
    v["filter"] = kind;
    auto r = (*s)->run(*d, v);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_TRUE(std::isfinite(r->get()->metrics.at("rmse")));
  }
}

TEST(ImmModelFormat, AGridGainsItsKeysAndFollowsThem) {
  json p = imm_base_preset();
  p["parameters"]["q_true"] = fmt_param(0.7, 0.0, 10);
  p["model"]["modes"] = {
      {"grid", {{{"param", "q"}, {"min", 0.1}, {"max", 2.0}, {"n", 5}, {"truth", "q_col"}}}}};
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  for (const char* key : {"grid.q.min", "grid.q.max", "grid.q.n", "markov.stay"})
    EXPECT_NE((*s)->params().find(key), nullptr) << key;
  ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok());
  Dataset data = *d;
  data.names.push_back("q_col");
  data.columns.emplace_back(data.rows(), 0.1);
  auto r = (*s)->run(data, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& res = dynamic_cast<const model::ModelResult&>(**r);
  EXPECT_EQ(res.metrics.at("imm.modes"), 5.0);
  ASSERT_EQ(res.imm->axes.size(), 1u);
  EXPECT_EQ(res.imm->axes[0].n, 5u);
  EXPECT_EQ(res.imm->axes[0].values, (std::vector<double>{0.1, 0.575, 1.05, 1.525, 2.0}));
  for (double e : res.imm->axes[0].estimate)
    EXPECT_TRUE(e >= 0.1 && e <= 2.0) << e;
  EXPECT_TRUE(std::isfinite(res.metrics.at("rmse.q")));
  const auto table = res.table();
  EXPECT_TRUE(table.has("mu.g4"));
  EXPECT_TRUE(table.has("imm.q"));
  EXPECT_TRUE(table.has("imm.map"));
  // New axes re-run the IMM with the new grid; a bad one is refused naming the keys.
  v["grid.q.n"] = 3;
  v["grid.q.min"] = 0.5;
  r = (*s)->run(data, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& res3 = dynamic_cast<const model::ModelResult&>(**r);
  EXPECT_EQ(res3.metrics.at("imm.modes"), 3.0);
  EXPECT_EQ(res3.imm->axes[0].values, (std::vector<double>{0.5, 1.25, 2.0}));
  v["grid.q.min"] = 3.0;
  r = (*s)->run(data, v);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "m.json: grid.q.min (3) must not exceed grid.q.max (2)");
}

TEST(ImmModelFormat, TwoAxesShareDeclaredKeysFirstAxisFastest) {
  json p = imm_base_preset();
  p["parameters"]["grid.min"] = fmt_param(0.1, 1e-3, 10);
  p["parameters"]["grid.max"] = fmt_param(1.0, 1e-3, 10);
  p["parameters"]["grid.n_q"] = {{"value", 2}, {"min", 1}, {"max", 9}, {"scale", "integer"}};
  p["parameters"]["grid.n_r"] = {{"value", 3}, {"min", 1}, {"max", 9}, {"scale", "integer"}};
  p["model"]["modes"] = {
      {"grid",
       {{{"param", "q"}, {"min", "grid.min"}, {"max", "grid.max"}, {"n", "grid.n_q"}},
        {{"param", "r"}, {"min", "grid.min"}, {"max", "grid.max"}, {"n", "grid.n_r"}}}},
      {"markov", {{"stay", 0.9}}}};
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  EXPECT_EQ((*s)->params().find("grid.q.min"), nullptr);
  ParamValues v = (*s)->params().defaults();
  auto d = (*s)->simulate(v);
  ASSERT_TRUE(d.ok());
  auto r = (*s)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& res = dynamic_cast<const model::ModelResult&>(**r);
  ASSERT_EQ(res.imm->modes(), 6u);
  EXPECT_EQ(res.imm->axes[0].values, (std::vector<double>{0.1, 1.0, 0.1, 1.0, 0.1, 1.0}));
  EXPECT_EQ(res.imm->axes[1].values, (std::vector<double>{0.1, 0.1, 0.55, 0.55, 1.0, 1.0}));
  // Each axis's values with as few decimals as tell them apart: q's 0.1 and 1.0, r's 0.55.
  EXPECT_EQ(res.imm->labels[3], "q = 1.0, r = 0.55");
}

TEST(ImmModelFormat, AnUnstableUnobservedStateEndsTheRunNamingIt) {
  // Found by the model-file fuzzer on an IMM seed: F = [[1, dt], [5, 1]] grows P by ~1.5 a step
  // while H = 0 observes nothing, so x stays 0 and P overflowed unnoticed (a debug build aborted
  // in the next update's covariance check). With and without modes: exit 1 naming the state.
  int refused_runs = 0;
  for (bool modes : {false, true}) {
    json p = imm_base_preset();
    p["model"]["process"]["F"][1][0] = "5";
    p["model"]["measurements"]["pos"]["H"][0][0] = "0";
    p["parameters"]["sim.dt"] = fmt_param(0.01, 0.001, 1);
    p["parameters"]["sim.duration"] = fmt_param(20, 1, 100);
    if (modes) p["model"]["modes"] = imm_two_modes();
    auto s = make_model_scenario(p, "m.json");
    ASSERT_TRUE(s.ok()) << s.error();
    const ParamValues v = (*s)->params().defaults();
    auto d = (*s)->simulate(v);
    ASSERT_TRUE(d.ok()) << d.error();
    auto r = (*s)->run(*d, v);
    ASSERT_FALSE(r.ok()) << modes;
    ++refused_runs;
    EXPECT_EQ(r.exit_code(), 1);
    EXPECT_NE(r.error().find("the variance of 'v' is not finite (P overflowed"), std::string::npos)
        << r.error();
  }
  EXPECT_EQ(refused_runs, 2);
}

// Grid values in labels and ticks: the fewest decimals that put every value within a twentieth of
// the step; one value, or values 10 decimals cannot place, keep number()'s form.
TEST(ImmModelFormat, GridValuesReadWithTheDecimalsTheirStepNeeds) {
  using model::grid_decimals;
  using model::grid_value_text;
  const auto seven = model::ModesSpec::axis_values(-0.05, 0.05, 7);
  EXPECT_EQ(grid_decimals(seven), 3);
  EXPECT_EQ(grid_value_text(seven[1], 3), "-0.033");
  EXPECT_EQ(grid_value_text(-1e-18, 3), "0.000");  // no "-0.000"
  EXPECT_EQ(grid_decimals({2.0, 2.5, 3.0}), 1);
  EXPECT_EQ(grid_decimals({1000.0, 2000.0, 3000.0}), 0);
  EXPECT_EQ(grid_decimals({0.5}), -1);
  EXPECT_EQ(grid_value_text(0.5, -1), "0.5");
  EXPECT_EQ(grid_decimals({0.0, 1e-12}), -1);  // a step below 10 decimals
  EXPECT_EQ(grid_value_text(1e300, 2), "1e+300");
}

// A grid over a name the preset does not declare (a mode parameter): a symbol of the expressions
// with no slider, its gained keys ranging over three times the span, its value outside the modes
// the grid's centre; a name that is taken or not a name is refused naming the key.
TEST(ImmModelFormat, AGridOverAnUndeclaredNameIsAModeParameter) {
  json p = imm_base_preset();
  p["model"]["measurements"]["pos"]["R"] = fmt_list({"(r*s)^2"});
  p["model"]["modes"] = {
      {"grid", {{{"param", "s"}, {"min", 0.5}, {"max", 1.5}, {"n", 3}, {"unit", "m/m"}}}}};
  auto sc = make_model_scenario(p, "m.json");
  ASSERT_TRUE(sc.ok()) << sc.error();
  const ParamTable& t = (*sc)->params();
  EXPECT_EQ(t.find("s"), nullptr);  // no slider
  ASSERT_NE(t.find("grid.s.min"), nullptr);
  EXPECT_DOUBLE_EQ(t.find("grid.s.min")->min, -1.0);  // [0.5 − 1.5, 1.5 + 1.5]
  EXPECT_DOUBLE_EQ(t.find("grid.s.max")->max, 3.0);
  ParamValues v = t.defaults();
  auto d = (*sc)->simulate(v);  // the model simulates itself at s = 1, the centre
  ASSERT_TRUE(d.ok()) << d.error();
  auto r = (*sc)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  const auto& res = dynamic_cast<const model::ModelResult&>(**r);
  ASSERT_EQ(res.imm->axes.size(), 1u);
  EXPECT_EQ(res.imm->axes[0].values, (std::vector<double>{0.5, 1.0, 1.5}));
  EXPECT_EQ(res.imm->axes[0].unit, "m/m");
  EXPECT_EQ(res.imm->labels[2], "s = 1.5");
  v["grid.s.min"] = 0.9;  // the keys move the grid
  r = (*sc)->run(*d, v);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(dynamic_cast<const model::ModelResult&>(**r).imm->axes[0].values.front(), 0.9);
  // --set of the mode parameter itself: not a key.
  ParamValues bad = t.defaults();
  bad["s"] = 1.0;
  EXPECT_FALSE((*sc)->run(*d, bad).ok());
  // An axis near the largest double: the gained keys' ranges stay finite, the value is refused.
  json huge = p;
  huge["model"]["modes"]["grid"][0]["min"] = -1e308;
  EXPECT_EQ(imm_load_error(huge),
            "m.json: model.modes.grid[0].min: -1e+308 is outside the range [-1e+300, 1e+300] of "
            "grid.s.min");
  p["model"]["modes"]["grid"][0]["param"] = "t";
  EXPECT_EQ(imm_load_error(p), "m.json: model.modes.grid[0].param: 't' is reserved");
  p["model"]["modes"]["grid"][0]["param"] = "x";  // a state's name: taken when the states come
  EXPECT_NE(imm_load_error(p).find("model.states"), std::string::npos) << imm_load_error(p);
}

// model.first_panels: names of the view's panels (model::panel_names), each once; refused
// otherwise, naming the key and the nearest names.
TEST(ImmModelFormat, FirstPanelsNameTheViewsPanels) {
  json p = imm_base_preset();
  p["model"]["modes"] = imm_two_modes();
  p["model"]["version"] = 2;
  p["model"]["first_panels"] = fmt_list({"mode_probabilities", "state.v"});
  auto s = make_model_scenario(p, "m.json");
  ASSERT_TRUE(s.ok()) << s.error();
  const auto layout = model_layout_of(**s);
  ASSERT_TRUE(layout);
  EXPECT_EQ(layout->first_panels, (std::vector<std::string>{"mode_probabilities", "state.v"}));
  EXPECT_EQ(layout->panels,
            (std::vector<std::string>{"state.x", "state.v", "measured.pos.z", "innovation.pos.z",
                                      "nis.pos", "gain", "mode_probabilities"}));
  p["model"]["first_panels"] = fmt_list({"state.w"});
  EXPECT_NE(imm_load_error(p).find("m.json: model.first_panels[0]: unknown panel 'state.w'"),
            std::string::npos)
      << imm_load_error(p);
  p["model"]["first_panels"] = fmt_list({"gain", "gain"});
  EXPECT_EQ(imm_load_error(p), "m.json: model.first_panels[1]: 'gain' twice");
  p["model"]["first_panels"] = "gain";
  EXPECT_EQ(imm_load_error(p), "m.json: model.first_panels: expected a list of panel names");
}

}  // namespace
}  // namespace kfw
