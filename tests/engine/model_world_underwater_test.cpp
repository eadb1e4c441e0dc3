// Issue 27: seed 004 as a model file (presets/models/underwater_world.json, staged until it
// replaces presets/underwater.json). Its world draws the built-in underwater simulator's streams
// (core/random.h: noise.n_u, noise.n_w, noise.n_r per 0.01 s step, clock.SENSOR, channel.SENSOR,
// noise.n_c per t_gap window, dropout.rangeN, outliers.range), so its simulated data equal the
// built-in's to 1e-12 of each column's largest magnitude (../shared/STAGE.md, "Randomness").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/model_files.h"
#include "core/dataset.h"
#include "core/scenario.h"

namespace kfw {
namespace world_underwater_test {
namespace {

const std::string kFile = KFW_SOURCE_DIR "/presets/models/underwater_world.json";

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

TEST(ModelWorldUnderwater, KeepsTheSeedPresetsParameterKeys) {
  auto builtin = make_scenario("underwater");
  ASSERT_TRUE(builtin.ok());
  auto model = testing::load_model_file(kFile);
  ASSERT_TRUE(model);
  for (const auto& spec : (*builtin)->params().specs()) {
    const ParamSpec* p = model->params().find(spec.key);
    ASSERT_TRUE(p) << spec.key;
  }
}

// Seeds 1..20, 60 s, with range dropouts and the default 276 outliers (over fewer samples).
TEST(ModelWorldUnderwater, TheWorldSimulatesWhatTheBuiltInSimulates) {
  auto builtin = make_scenario("underwater");
  ASSERT_TRUE(builtin.ok());
  auto model = testing::load_model_file(kFile);
  ASSERT_TRUE(model);
  for (int seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    ParamValues vb = (*builtin)->params().defaults(), vm = model->params().defaults();
    for (auto* v : {&vb, &vm}) {
      (*v)["sim.seed"] = seed;
      (*v)["sim.duration"] = 60;
      (*v)["sim.range_dropout"] = 0.1;
    }
    auto db = (*builtin)->simulate(vb);
    ASSERT_TRUE(db.ok()) << db.error();
    auto dm = model->simulate(vm);
    ASSERT_TRUE(dm.ok()) << dm.error();
    EXPECT_TRUE(same_data(*db, *dm, 1e-12));
  }
}

}  // namespace
}  // namespace world_underwater_test
}  // namespace kfw
