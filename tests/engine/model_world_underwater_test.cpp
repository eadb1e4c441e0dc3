// Issue 27: seed 004 as a model file (presets/underwater.json, staged as
// presets/models/underwater_world.json until it replaced the built-in's preset). Its world draws
// the built-in underwater simulator's streams (core/random.h: noise.n_u, noise.n_w, noise.n_r per
// 0.01 s step, clock.SENSOR, channel.SENSOR, noise.n_c per t_gap window, dropout.rangeN,
// outliers.range), so its simulated data equal the built-in's to 1e-12 of each column's largest
// magnitude (../shared/STAGE.md, "Randomness"). Since issue 30 the built-in's simulator is the
// oracle tests/oracles/underwater/underwater_sim.h, and its preset the fixture
// tests/fixtures/preset_v2/underwater.json.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "common/model_files.h"
#include "core/dataset.h"
#include "core/scenario.h"
#include "model/model_scenario.h"
#include "oracles/underwater/underwater_params.h"
#include "oracles/underwater/underwater_sim.h"

namespace kfw {
namespace world_underwater_test {
namespace {

const std::string kFile = KFW_SOURCE_DIR "/presets/underwater.json";

// Every column of the built-in's data in the model's, row by row: the same samples (NaN where no
// sample) and values within tol of the column's largest magnitude.
::testing::AssertionResult same_data(const Dataset& b, const Dataset& m, double tol) {
  if (b.rows() != m.rows()) {
    return ::testing::AssertionFailure() << "rows " << m.rows() << " vs " << b.rows();
  }
  for (std::size_t c = 0; c < b.columns.size(); ++c) {
    const std::string& name = b.names[c];
    if (!m.has(name)) return ::testing::AssertionFailure() << "no column " << name;
    const auto& x = m.col(name);
    const auto& y = b.columns[c];
    double scale = 0;
    for (double v : y) {
      if (std::isfinite(v)) scale = std::max(scale, std::fabs(v));
    }
    for (std::size_t k = 0; k < y.size(); ++k) {
      if (std::isnan(x[k]) != std::isnan(y[k]) ||
          (!std::isnan(y[k]) && !(std::fabs(x[k] - y[k]) <= tol * scale))) {
        return ::testing::AssertionFailure() << name << " row " << k << ": " << x[k] << " vs "
                                             << y[k] << " (t = " << b.columns[0][k] << ")";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

// The built-in's preset (its table, every key) is the fixture; the file keeps each entry as it was
// and adds only sim.dt, the world's motion step (the built-in's fixed 0.01 s).
TEST(ModelWorldUnderwater, KeepsTheSeedPresetsParameterKeys) {
  std::ifstream old_in(KFW_SOURCE_DIR "/tests/fixtures/preset_v2/underwater.json");
  std::ifstream new_in(kFile);
  const auto old_preset = nlohmann::json::parse(old_in);
  const auto new_preset = nlohmann::json::parse(new_in);
  EXPECT_EQ(old_preset.at("scenario"), "underwater");
  EXPECT_EQ(new_preset.at("scenario"), "model");
  EXPECT_EQ(std::filesystem::path(old_preset.value("data", "")).filename(),
            std::filesystem::path(new_preset.value("data", "")).filename());
  const auto& was = old_preset.at("parameters");
  const auto& now = new_preset.at("parameters");
  EXPECT_EQ(was.size(), 31u);
  for (const auto& [key, entry] : was.items()) {
    ASSERT_TRUE(now.contains(key)) << key;
    EXPECT_EQ(now.at(key), entry) << key;
  }
  for (const auto& [key, entry] : now.items())
    EXPECT_TRUE(was.contains(key) || key == "sim.dt") << key;
  auto model = testing::load_model_file(kFile);
  ASSERT_TRUE(model);
  for (const auto& [key, entry] : was.items())
    EXPECT_TRUE(model->params().find(key)) << key;
  EXPECT_EQ(model->params().defaults().at("sim.dt"), underwater::kMotionDt_s);
}

// The oracle simulator's (the retired built-in's) and the model file's simulations of seeds 1..20
// (60 s), each with the values `set` gives for its seed, compared by `check`.
template <class Set, class Check>
void simulate_both(const Set& set, const Check& check) {
  auto model = testing::load_model_file(kFile);
  ASSERT_TRUE(model);
  for (int seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    ParamValues v = model->params().defaults();
    v["sim.seed"] = seed;
    v["sim.duration"] = 60;
    set(seed, v);
    const Dataset db = underwater::simulate(underwater::sim_params(v));
    auto dm = model->simulate(v);
    ASSERT_TRUE(dm.ok()) << dm.error();
    check(v, db, *dm);
  }
}

// Seeds 1..20, 60 s, with range dropouts and the default 276 outliers (over fewer samples).
TEST(ModelWorldUnderwater, TheWorldSimulatesWhatTheBuiltInSimulates) {
  simulate_both([](int, ParamValues& v) { v["sim.range_dropout"] = 0.1; },
                [](const ParamValues&, const Dataset& b, const Dataset& m) {
                  EXPECT_TRUE(same_data(b, m, 1e-12));
                });
}

// Synchronous clocks (sim.clock, a choice between the world's shared clock "sync" and each
// sensor's own): every sensor on the ticks of the stream clock.sync, as the built-in — seeds
// 1..20, two periods.
TEST(ModelWorldUnderwater, SynchronousClocksSimulateWhatTheBuiltInSimulates) {
  simulate_both(
      [](int seed, ParamValues& v) {
        v["sim.clock"] = 0;  // synchronous
        v["sim.dt_sync"] = seed % 2 ? 0.1 : 0.25;
      },
      [](const ParamValues& v, const Dataset& b, const Dataset& m) {
        const double ticks = 60 / v.at("sim.dt_sync");  // every sensor on one clock: a row a tick
        EXPECT_NEAR(static_cast<double>(m.rows()), ticks, 0.02 * ticks);
        EXPECT_TRUE(same_data(b, m, 1e-12));
      });
}

// A sensor's clock chosen by a parameter: each mistake named with its key.
TEST(ModelWorldUnderwater, ClockAlternativesAreCheckedAtLoad) {
  struct Case {
    const char* edit;  // a JSON merge patch of model.world.measurements.depth.clock
    std::string want;
  };
  const Case cases[] = {
      {R"({"synchronous": "snyc"})",
       "model.world.measurements.depth.clock.synchronous: unknown clock 'snyc' (did you mean "
       "'sync'?)"},
      {R"({"asynchronous": null})",
       "model.world.measurements.depth.clock: missing the clock for 'sim.clock' = 'asynchronous'"},
      {R"({"param": "scheme"})",
       "model.world.measurements.depth.clock.asynchronous: unknown choice of 'scheme' "
       "'asynchronous'"},
      {R"({"param": "sim.clok"})",
       "model.world.measurements.depth.clock.param: unknown choice parameter 'sim.clok' (did you "
       "mean "
       "'sim.clock'?)"},
      {R"({"hourly": "sync"})",
       "model.world.measurements.depth.clock.hourly: unknown choice of 'sim.clock' 'hourly'"},
  };
  for (const auto& c : cases) {
    std::ifstream in(kFile);
    auto j = nlohmann::json::parse(in);
    j["model"]["world"]["measurements"]["depth"]["clock"].merge_patch(
        nlohmann::json::parse(c.edit));
    auto s = make_model_scenario(j, "uw.json");
    ASSERT_FALSE(s.ok()) << c.edit;
    EXPECT_NE(s.error().find(c.want), std::string::npos) << s.error();
  }
}

}  // namespace
}  // namespace world_underwater_test
}  // namespace kfw
